//! The figures: for each, its id, file name, the paper's title, what it plots and the
//! first part of its caption.

/// What a figure plots.
#[derive(Clone, Copy, Debug)]
pub(super) enum Plot {
    /// The tips of the unit vectors of an orientation matrix (columns `{matrix}_1j`…).
    Orientation { matrix: &'static str },
    /// A vector's components (columns `{prefix}_x`, `_y`, `_z`) against time.
    Time(Quantity),
    /// A vector's components against the crank angle, wrapped.
    Angle(Quantity),
    /// The output slider over a revolution against the rigid kinematics.
    OutputSlider,
    /// The energy balance.
    EnergyBalance,
}

/// A recorded vector and how to describe it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Quantity {
    /// Column prefix.
    pub(super) prefix: &'static str,
    /// The y axis's description, with its unit.
    pub(super) y_label: &'static str,
    /// Its unit, for the caption.
    pub(super) unit: &'static str,
    /// What the caption reports: the largest magnitude, or each component's range.
    pub(super) stat: Stat,
}

/// What a caption reports about a [`Quantity`].
#[derive(Clone, Copy, Debug)]
pub(super) enum Stat {
    Peak,
    Span,
}

/// A figure: id, file name, the paper's title, content, and the caption's first part.
pub(super) struct Figure {
    pub(super) id: &'static str,
    pub(super) name: &'static str,
    pub(super) title: &'static str,
    pub(super) plot: Plot,
    pub(super) about: &'static str,
}

const fn quantity(prefix: &'static str, y_label: &'static str, unit: &'static str) -> Quantity {
    Quantity {
        prefix,
        y_label,
        unit,
        stat: Stat::Peak,
    }
}

const fn position(prefix: &'static str, y_label: &'static str) -> Quantity {
    Quantity {
        prefix,
        y_label,
        unit: "m",
        stat: Stat::Span,
    }
}

const H1: Quantity = quantity("h1", "angular momentum h1 (kg·m²/s)", "kg·m²/s");
const F_O1: Quantity = quantity("F_O1", "force at O1 on the crank (N)", "N");
const TC: Quantity = quantity("Tc", "torque Tc on the crank (N·m)", "N·m");
const F_A2: Quantity = quantity("F_A2", "force at A2 on the slider (N)", "N");
const R_C3: Quantity = position("r_C3", "position of C3 (m)");
const P3: Quantity = quantity("p3", "translational momentum p3 (kg·m/s)", "kg·m/s");
const F_O3: Quantity = quantity("F_O3", "force at O3 on the rocker (N)", "N");
const R_C5: Quantity = position("r_C5", "position of C5 (m)");
const P5: Quantity = quantity("p5", "translational momentum p5 (kg·m/s)", "kg·m/s");
const F_O5: Quantity = quantity("F_O5", "force at O5 on slider 2 (N)", "N");

/// Every figure, in order.
pub(super) const FIGURES: [Figure; N_FIGURES] = [
    Figure {
        id: "fig03",
        name: "fig03_orientation_crank_3d",
        title: "Variation of orientation matrix of link 1 with time",
        plot: Plot::Orientation { matrix: "R1" },
        about: "The unit vectors of the crank's frame 1 expressed in frame 0 (the columns \
                of the orientation matrix [⁰₁R], columns R1_11 … R1_33), their tips traced \
                in 3-D over the run. The x and y unit vectors turn on the unit circle in \
                the X0-Y0 plane; the z unit vector stays at (0, 0, 1).",
    },
    Figure {
        id: "fig04",
        name: "fig04_angular_momentum_crank_vs_time",
        title: "Variation of angular momentum of link 1 with time",
        plot: Plot::Time(H1),
        about: "The crank's angular momentum about its centre of mass (h1_x, h1_y, h1_z). \
                The z component is almost constant after the start-up transient where \
                the crank is driven at w_drive through the compliant coupling K_C, R_C, \
                and exactly constant where a flow source turns it (quick_return_rigid).",
    },
    Figure {
        id: "fig05",
        name: "fig05_force_O1_vs_time",
        title: "Variation of force at fixed end of crank with time",
        plot: Plot::Time(F_O1),
        about: "The force the ground coupling K01, R01 exerts on the crank at its pivot O1 \
                (F_O1_x, F_O1_y, F_O1_z), against time.",
    },
    Figure {
        id: "fig06",
        name: "fig06_force_O1_vs_crank_angle",
        title: "Variation of force at fixed end of crank with crank angle",
        plot: Plot::Angle(F_O1),
        about: "The force at the crank's pivot O1, as in Fig. 5, against the crank angle.",
    },
    Figure {
        id: "fig07",
        name: "fig07_torque_Tc_vs_time",
        title: "Variation of torque Tc on the crank with time",
        plot: Plot::Time(TC),
        about: "The torque the drive coupling K_C, R_C exerts on the crank (Tc_x, Tc_y, \
                Tc_z), against time. It is largest at the start, when the flow source \
                w_drive is applied suddenly to the crank at rest.",
    },
    Figure {
        id: "fig08",
        name: "fig08_torque_Tc_vs_crank_angle",
        title: "Variation of torque Tc on the crank with crank angle",
        plot: Plot::Angle(TC),
        about: "The drive torque, as in Fig. 7, against the crank angle; the start-up \
                transient is at the initial crank angle theta0.",
    },
    Figure {
        id: "fig09",
        name: "fig09_force_A2_vs_time",
        title: "Variation of force at pin connecting crank and slider at point A2 on slider \
                with time",
        plot: Plot::Time(F_A2),
        about: "The force the crank pin coupling K12, R12 exerts on the slider at A2 \
                (F_A2_x, F_A2_y, F_A2_z), against time.",
    },
    Figure {
        id: "fig10",
        name: "fig10_force_A2_vs_crank_angle",
        title: "Variation of force at pin connecting crank and slider at point A2 on slider \
                with crank angle",
        plot: Plot::Angle(F_A2),
        about: "The force on the slider at A2, as in Fig. 9, against the crank angle.",
    },
    Figure {
        id: "fig11",
        name: "fig11_position_C3_vs_time",
        title: "Variation of coordinates of center of mass of rocker arm with time",
        plot: Plot::Time(R_C3),
        about: "The position of the rocker arm's centre of mass C3 in frame 0 (r_C3_x, \
                r_C3_y, r_C3_z). The steeper parts are the quick return strokes.",
    },
    Figure {
        id: "fig12",
        name: "fig12_momentum_rocker_vs_time",
        title: "Variation of translational momentum of rocker arm with time",
        plot: Plot::Time(P3),
        about: "The rocker arm's translational momentum (p3_x, p3_y, p3_z); its peaks are \
                larger during the return stroke than during the forward stroke.",
    },
    Figure {
        id: "fig13",
        name: "fig13_force_O3_vs_time",
        title: "Variation of force at fixed end of rocker arm with time",
        plot: Plot::Time(F_O3),
        about: "The force the ground coupling K03, R03 exerts on the rocker arm at its \
                pivot O3 (F_O3_x, F_O3_y, F_O3_z), against time.",
    },
    Figure {
        id: "fig14",
        name: "fig14_force_O3_vs_crank_angle",
        title: "Variation of force at fixed end of rocker arm with crank angle",
        plot: Plot::Angle(F_O3),
        about: "The force at the rocker's pivot O3, as in Fig. 13, against the crank angle.",
    },
    Figure {
        id: "fig15",
        name: "fig15_orientation_rod_3d",
        title: "Variation of orientation matrix of link 4 with time",
        plot: Plot::Orientation { matrix: "R4" },
        about: "The unit vectors of the connecting rod's frame 4 expressed in frame 0 (the \
                columns of [⁰₄R], columns R4_11 … R4_33), their tips traced in 3-D over \
                the run. The x and y unit vectors swing to and fro on an arc of the unit \
                circle; the z unit vector stays at (0, 0, 1).",
    },
    Figure {
        id: "fig16",
        name: "fig16_position_C5_vs_time",
        title: "Variation of coordinates of center of mass of slider 2 with time",
        plot: Plot::Time(R_C5),
        about: "The position of the output slider's (slider 2, link 5) centre of mass in \
                frame 0 (r_C5_x, r_C5_y, r_C5_z): it reciprocates along X0, moving more \
                steeply during the quick return.",
    },
    Figure {
        id: "fig17",
        name: "fig17_momentum_slider2_vs_time",
        title: "Variation of the components of translational momentum with time",
        plot: Plot::Time(P5),
        about: "The translational momentum of the output slider (slider 2, link 5) (p5_x, \
                p5_y, p5_z); the peaks of the x component are larger during the return \
                stroke (positive) than during the forward stroke (negative).",
    },
    Figure {
        id: "fig18",
        name: "fig18_force_O5_vs_time",
        title: "Variation of force at the center of mass of slider 2 with time",
        plot: Plot::Time(F_O5),
        about: "The force the connecting rod's coupling K45, R45 exerts on the output \
                slider at O5 (F_O5_x, F_O5_y, F_O5_z), against time.",
    },
    Figure {
        id: "fig19",
        name: "fig19_force_O5_vs_crank_angle",
        title: "Variation of force at center of mass of slider 2 with crank angle",
        plot: Plot::Angle(F_O5),
        about: "The force on the output slider at O5, as in Fig. 18, against the crank \
                angle.",
    },
    Figure {
        id: "fig20",
        name: "fig20_output_slider_vs_rigid",
        title: "Output slider over the last crank revolution: model and rigid kinematics (not \
                in the paper)",
        plot: Plot::OutputSlider,
        about: "",
    },
    Figure {
        id: "fig21",
        name: "fig21_energy_balance",
        title: "Energy balance over time (not in the paper)",
        plot: Plot::EnergyBalance,
        about: "",
    },
];

pub(super) const N_FIGURES: usize = 19;

const fn figure_ids() -> [&'static str; N_FIGURES] {
    let mut ids = [""; N_FIGURES];
    let mut i = 0;
    while i < N_FIGURES {
        ids[i] = FIGURES[i].id;
        i += 1;
    }
    ids
}

pub(super) const IDS: [&str; N_FIGURES] = figure_ids();

/// The number of the paper's figure `id` (`fig05` → 5).
pub(super) fn number(id: &str) -> &str {
    id.trim_start_matches("fig").trim_start_matches('0')
}
