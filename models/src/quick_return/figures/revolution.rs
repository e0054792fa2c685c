//! Fig. 20 (not in the paper): the output slider over the last full crank revolution
//! against the rigid-body kinematics.

use core::f64::consts::TAU;
use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::plot::{
    draw_stacked_charts, wrap_by_revolution, ChartOptions, ImageFormat, LineChart, PlotError,
    Series, SeriesStyle, WIDTH,
};
use crate::quick_return::results::CRANK_ANGLE;
use crate::quick_return_rigid::{rigid_state, Motion, RigidParams};

use super::{revolution_axis, significant, Data, PANEL_HEIGHT};

/// Picks the value, rate or acceleration of a rigid [`Motion`].
type Pick = fn(&Motion) -> f64;

impl Data<'_> {
    /// The samples of the last full crank revolution: from the last sample at or
    /// before `θ_end − 2π` to the end. `None` if the crank did not turn a full
    /// revolution.
    fn last_revolution(&self) -> Option<Range<usize>> {
        let angle = self.column(CRANK_ANGLE);
        let end = angle.iter().rposition(|a| a.is_finite())?;
        let target = angle[end] - TAU;
        let start = angle[..end].iter().rposition(|&a| a <= target)?;
        Some(start..end + 1)
    }

    pub(super) fn output_slider(
        &self,
        title: &str,
        path: &Path,
        formats: &[ImageFormat],
    ) -> Result<(String, Vec<PathBuf>), PlotError> {
        let Some(rows) = self.last_revolution() else {
            let note = format!(
                "Not drawn: the crank did not turn a full revolution in this run ({}), so \
                 there is no revolution to compare with the rigid kinematics.",
                self.span()
            );
            return Ok((note, Vec::new()));
        };
        let slider = SliderRevolution::new(self, rows);
        let charts = slider.charts();
        let options = ChartOptions {
            size: (WIDTH, PANEL_HEIGHT),
            styles: vec![
                SeriesStyle::solid((31, 119, 180)),
                SeriesStyle::dashed((0, 0, 0)),
                SeriesStyle::solid((255, 127, 14)),
            ],
            ..revolution_axis()
        };
        let files = draw_stacked_charts(
            title,
            &charts,
            &[options.clone(), options.clone(), options],
            path,
            formats,
        )?;
        Ok((slider.caption(self.results.times()), files))
    }
}

/// The output slider over the last revolution, from the model and from the rigid
/// kinematics.
struct SliderRevolution<'a> {
    /// The model's name.
    model: &'static str,
    rows: Range<usize>,
    /// Unwrapped crank angle, position, velocity and acceleration of the model.
    angle: &'a [f64],
    motion: [Vec<f64>; 3],
    /// The crank's own speed, h1_z / J1z.
    crank_speed: Vec<f64>,
    rigid: RigidParams,
    drive_speed: f64,
}

impl<'a> SliderRevolution<'a> {
    fn new(data: &'a Data<'_>, rows: Range<usize>) -> Self {
        let column = |name| &data.column(name)[rows.clone()];
        let rigid = data.mechanism.rigid.clone();
        let m5 = rigid.m5;
        let j1z = rigid.inertias_z()[0];
        let velocity = column("p5_x").iter().map(|p| p / m5).collect();
        let acceleration = column("F_O5_x")
            .iter()
            .zip(column("F_5C_x"))
            .map(|(f, g)| (f + g) / m5)
            .collect();
        SliderRevolution {
            model: data.results.model_name(),
            angle: column(CRANK_ANGLE),
            motion: [column("r_C5_x").to_vec(), velocity, acceleration],
            crank_speed: column("h1_z").iter().map(|h| h / j1z).collect(),
            rows,
            rigid,
            drive_speed: data.mechanism.drive_speed,
        }
    }

    /// The rigid output slider's motion at crank angle `theta` turning at `speed`.
    fn rigid_at(&self, theta: f64, speed: f64) -> Motion {
        rigid_state(theta, speed, 0.0, &self.rigid).output_x
    }

    /// The velocity the rigid mechanism would have at each sample's crank angle and
    /// the crank's own speed there.
    fn rigid_velocity_at_crank_speed(&self) -> Vec<f64> {
        self.angle
            .iter()
            .zip(&self.crank_speed)
            .map(|(&th, &w)| self.rigid_at(th, w).rate)
            .collect()
    }

    /// The largest difference between `values` and the rigid kinematics `pick`ed at the
    /// same crank angle and the drive speed.
    fn worst(&self, values: &[f64], pick: Pick) -> f64 {
        self.angle
            .iter()
            .zip(values)
            .map(|(&th, &v)| (v - pick(&self.rigid_at(th, self.drive_speed))).abs())
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max)
    }

    fn charts(&self) -> Vec<LineChart> {
        let grid: Vec<f64> = (0..=720).map(|i| TAU * f64::from(i) / 720.0).collect();
        let panels: [(&str, &str, Pick); 3] = [
            ("position", "position x of C5 (m)", |m| m.value),
            ("velocity", "velocity (m/s)", |m| m.rate),
            ("acceleration", "acceleration (m/s²)", |m| m.accel),
        ];
        let mut charts = Vec::new();
        for (k, (what, y_label, pick)) in panels.into_iter().enumerate() {
            let rigid = grid
                .iter()
                .map(|&th| (th, pick(&self.rigid_at(th, self.drive_speed))))
                .collect();
            let mut series = vec![
                Series::new("model", wrap_by_revolution(self.angle, &self.motion[k])),
                Series::new(format!("rigid, {} rad/s", self.drive_speed), rigid),
            ];
            if what == "velocity" {
                let at_speed = self.rigid_velocity_at_crank_speed();
                series.push(Series::new(
                    "rigid, crank's speed",
                    wrap_by_revolution(self.angle, &at_speed),
                ));
            }
            charts.push(LineChart {
                title: format!("Output slider {what}"),
                x_label: "crank angle θ (rad)".to_owned(),
                y_label: y_label.to_owned(),
                series,
            });
        }
        charts
    }

    fn caption(&self, t: &[f64]) -> String {
        let [x, v, a] = &self.motion;
        let finite = || self.crank_speed.iter().copied().filter(|w| w.is_finite());
        let (w_lo, w_hi) = (
            finite().reduce(f64::min).unwrap_or(f64::NAN),
            finite().reduce(f64::max).unwrap_or(f64::NAN),
        );
        let at_speed = self.rigid_velocity_at_crank_speed();
        let speed_gap = v
            .iter()
            .zip(&at_speed)
            .map(|(a, b)| (a - b).abs())
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max);
        format!(
            "Not in the paper. The output slider (slider 2, link 5) over the last full crank \
             revolution of the run (t = {} to {} s), against the crank angle wrapped to \
             [0, 2π), with the rigid-body kinematics of the ideal mechanism (dashed) at the \
             constant drive speed θ̇ = {} rad/s. The model ({}): position r_C5_x; \
             velocity p5_x/m5, from the recorded momentum (not a differentiated position); \
             acceleration (F_O5_x + F_5C_x)/m5, Newton's second law along X0 with the two \
             recorded joint forces on the slider (exact at the samples, no numerical \
             differentiation). Largest differences from the rigid kinematics at the same \
             crank angle: position {} m, velocity {} m/s, acceleration {} m/s². The crank's \
             own speed h1_z/J1z ranges from {} to {} rad/s over this revolution (a drive \
             through the compliant coupling K_C, R_C makes it vary). The rigid velocity at the crank's own speed (orange) \
             differs from the model's by at most {} m/s.",
            t[self.rows.start],
            t[self.rows.end - 1],
            self.drive_speed,
            self.model,
            significant(self.worst(x, |m| m.value)),
            significant(self.worst(v, |m| m.rate)),
            significant(self.worst(a, |m| m.accel)),
            significant(w_lo),
            significant(w_hi),
            significant(speed_gap),
        )
    }
}
