#![deny(warnings)]
// A C's linear law is a stiffness, e = k q. Written as 20-sim's compliance, `1.0 / k`,
// the shaft would be k² times too soft: the compiler says so (a warning, an error
// here under deny(warnings)), at the law, for a stiffness named like one or declared
// in N/m or N·m/rad. A capacitor's `1.0 / capacitance` is a stiffness and is left alone.
use bgdsl_runtime::bond_graph;

bond_graph! {
    pub model Shafts {
        param k_shaft = 4.0e5;
        param grip = 2.0e3 in "N·m/rad";
        param capacitance = 1.0e-5 in "F";
        param speed = 1.0 in "rad/s";
        Sf twist = speed;
        Sf slip = speed;
        Sf current = 1.0e-3;
        C shaft = 1.0 / k_shaft;
        C clutch = 1 / grip;
        C capacitor = 1.0 / capacitance;
        twist -> shaft;
        slip -> clutch;
        current -> capacitor;
    }
}

fn main() {}
