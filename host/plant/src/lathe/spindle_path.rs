//! The spindle's path while machining against its path while measuring, from its causes
//! (docs/domain.md §2.6, docs/accuracy.md "The spindle path"; error-analysis paper E, its
//! Fig. 1 and conclusions).
//!
//! The spindle is a rigid shaft on two radial supports, the front one (at the chuck) and
//! the rear one, `span_mm` (b) apart; the measured section lies `overhang_mm` (a) in front
//! of the front support. A radial force F at the section loads the front support with
//! `F·(a + b)/b` and the rear one with `−F·a/b`; the section moves by
//! `y = y_front·(a + b)/b − y_rear·a/b` when the supports move by `y_front`, `y_rear`. A
//! support moves by its load over its stiffness, and by half its radial clearance towards
//! a fixed load that outweighs the rotating one (a larger rotating load carries the journal
//! round the clearance once per revolution instead). The loads, along X (the tool's
//! direction, positive towards the tool):
//!
//! - the cutting force's radial component F_p, pushing the part away from the tool,
//!   **while machining only** (measuring touches with no force);
//! - the belt's pull on the rear support (the pulley taken at the rear support), its X
//!   component, in both states;
//! - the unbalance `U·ω²`, rotating with the part (fixed in the part's frame), at the
//!   machining speed while machining and at the measuring speed (the scenario's `rpm`)
//!   while measuring.
//!
//! The part was cut around the machining path, so what the tool reads while measuring is
//! the difference of the two paths at the section: a constant part (the supports' fixed
//! loads and clearance take-up differ) and a once-per-revolution part in the part's frame
//! (the unbalance's deflection at two speeds, and the clearance orbit where the rotating
//! load wins). Both are radius errors, µm, added to the seen surface only (the true one is
//! the part's). `SpindlePath::default()` is [`SpindlePath::typical`], a plausible small CNC
//! lathe (values and sources on it); [`SpindlePath::none`] has no loads, so the paths
//! coincide (the verification lathes and the papers' rigs, whose form profile is already the
//! surface the tool saw).

use super::surface::Harmonic;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The spindle's supports and loads (`[lathe.spindle_path]` in a settings file).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SpindlePath {
    /// Distance between the front and rear support, b, mm, `1..=5000`.
    pub span_mm: f64,
    /// Distance from the front support to the measured section, a, mm, `0..=5000`.
    pub overhang_mm: f64,
    /// Radial stiffness of the front support, N/µm, `1..=1e5`.
    pub front_stiffness_n_per_um: f64,
    /// Radial stiffness of the rear support, N/µm, `1..=1e5`.
    pub rear_stiffness_n_per_um: f64,
    /// Radial clearance of each support (play of the journal, diametral), µm, `0..=100`.
    pub clearance_um: f64,
    /// Radial component F_p of the cutting force while machining, N, `0..=1e5`.
    pub cutting_force_n: f64,
    /// X component of the belt's pull on the rear support, N, `-1e5..=1e5`.
    pub belt_load_n: f64,
    /// Unbalance of the spindle, chuck and part, U = m·e, g·mm, `0..=1e6`.
    pub unbalance_g_mm: f64,
    /// Angle of the unbalance from the index pulse, rad.
    pub unbalance_phase_rad: f64,
    /// Spindle speed while machining, rpm, `0..=1e6` (0: the measuring speed, `rpm`).
    pub machining_rpm: f64,
    /// Whether the loads act; `false`: the measuring path is the machining path, whatever
    /// the other fields say (`[lathe.spindle_path] loads = false`, as the fast
    /// verification lathes set it).
    pub loads: bool,
}

impl Default for SpindlePath {
    /// [`SpindlePath::typical`].
    fn default() -> Self {
        SpindlePath::typical()
    }
}

/// What the path difference does to the seen radius at the section.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PathDifference {
    /// The constant part, measuring path minus machining path at the section, µm (radius;
    /// positive: the tool reads the part larger).
    pub offset_um: f64,
    /// The once-per-revolution part in the part's frame, µm (radius).
    pub first_harmonic: Harmonic,
    /// The section's constant displacement while machining, µm.
    pub machining_um: f64,
    /// The section's constant displacement while measuring, µm.
    pub measuring_um: f64,
    /// The unbalance force while machining, N.
    pub unbalance_machining_n: f64,
    /// The unbalance force while measuring, N.
    pub unbalance_measuring_n: f64,
}

impl PathDifference {
    /// True when the paths coincide.
    pub fn is_zero(&self) -> bool {
        self.offset_um == 0.0 && self.first_harmonic.amplitude_um == 0.0
    }

    /// The seen radius's change at spindle angle `phi` (rad), µm.
    pub fn at(&self, phi: f64) -> f64 {
        self.offset_um + self.first_harmonic.at(phi)
    }
}

/// One support's constant and rotating displacement under a fixed and a rotating load.
fn support(fixed_n: f64, rotating_n: f64, stiffness: f64, clearance_um: f64) -> (f64, f64) {
    let half = clearance_um / 2.0;
    if fixed_n == 0.0 && rotating_n == 0.0 {
        // No load: the journal stays where it is, taken as the middle of the clearance.
        (0.0, 0.0)
    } else if fixed_n.abs() > rotating_n.abs() {
        // The fixed load holds the journal against one side of the clearance.
        (
            fixed_n / stiffness + half * fixed_n.signum(),
            rotating_n / stiffness,
        )
    } else {
        // The rotating load carries the journal round the clearance.
        (
            fixed_n / stiffness,
            rotating_n / stiffness + half * rotating_n.signum(),
        )
    }
}

impl SpindlePath {
    /// A plausible small CNC lathe, for the presets and `docs/accuracy.md`: the first rig's
    /// geometry (120 mm free length held in a chuck), supports of a few hundred N/µm
    /// (angular-contact spindle bearings), 4 µm diametral play (a worn or unpreloaded
    /// bearing), F_p 25 N (finishing mild steel: k_c ≈ 2000 N/mm² × a_p 0.25 mm × f 0.12
    /// mm/rev ≈ 60 N main force, F_p ≈ 0.4 of it), a 500 N belt component, unbalance
    /// 1200 g·mm (balance grade G 6.3 for 20 kg at 1000 rpm: e = 6.3 mm/s / ω ≈ 60 µm),
    /// machining at 1000 rpm.
    pub fn typical() -> SpindlePath {
        SpindlePath {
            span_mm: 300.0,
            overhang_mm: 120.0,
            front_stiffness_n_per_um: 500.0,
            rear_stiffness_n_per_um: 200.0,
            clearance_um: 4.0,
            cutting_force_n: 25.0,
            belt_load_n: 500.0,
            unbalance_g_mm: 1200.0,
            unbalance_phase_rad: 0.0,
            machining_rpm: 1000.0,
            loads: true,
        }
    }

    /// No loads: the measuring path is the machining path (`[lathe.spindle_path] loads =
    /// false`; the other fields are the typical lathe's and act on nothing).
    pub fn none() -> SpindlePath {
        SpindlePath {
            loads: false,
            ..SpindlePath::typical()
        }
    }

    /// True for the default ([`SpindlePath::typical`]): not written to a settings file.
    pub fn is_default(&self) -> bool {
        *self == SpindlePath::default()
    }

    /// The unbalance force at `rpm`, N: `U·ω²` (U in kg·m).
    pub fn unbalance_n(&self, rpm: f64) -> f64 {
        let omega = 2.0 * PI * rpm / 60.0;
        self.unbalance_g_mm * 1e-6 * omega * omega
    }

    /// The section's (constant, rotating) displacement, µm, under a fixed load `section_n`
    /// at the section, the belt on the rear support and a rotating load `rotating_n` at
    /// the section.
    fn section(&self, section_n: f64, rotating_n: f64) -> (f64, f64) {
        let (a, b) = (self.overhang_mm, self.span_mm);
        let front_lever = (a + b) / b;
        let rear_lever = a / b;
        let (front_fixed, front_rot) = support(
            section_n * front_lever,
            rotating_n * front_lever,
            self.front_stiffness_n_per_um,
            self.clearance_um,
        );
        let (rear_fixed, rear_rot) = support(
            self.belt_load_n - section_n * rear_lever,
            -rotating_n * rear_lever,
            self.rear_stiffness_n_per_um,
            self.clearance_um,
        );
        (
            front_fixed * front_lever - rear_fixed * rear_lever,
            front_rot * front_lever - rear_rot * rear_lever,
        )
    }

    /// The difference of the paths when measuring at `measuring_rpm`.
    pub fn difference(&self, measuring_rpm: f64) -> PathDifference {
        if !self.loads {
            return PathDifference {
                offset_um: 0.0,
                first_harmonic: Harmonic {
                    order: 1,
                    amplitude_um: 0.0,
                    phase_rad: 0.0,
                },
                machining_um: 0.0,
                measuring_um: 0.0,
                unbalance_machining_n: 0.0,
                unbalance_measuring_n: 0.0,
            };
        }
        let machining_rpm = if self.machining_rpm > 0.0 {
            self.machining_rpm
        } else {
            measuring_rpm
        };
        let (u_c, u_m) = (
            self.unbalance_n(machining_rpm),
            self.unbalance_n(measuring_rpm),
        );
        // The cutting force pushes the part away from the tool: −F_p along X.
        let (fixed_c, rot_c) = self.section(-self.cutting_force_n, u_c);
        let (fixed_m, rot_m) = self.section(0.0, u_m);
        PathDifference {
            offset_um: fixed_m - fixed_c,
            first_harmonic: Harmonic {
                order: 1,
                amplitude_um: rot_m - rot_c,
                phase_rad: self.unbalance_phase_rad,
            },
            machining_um: fixed_c,
            measuring_um: fixed_m,
            unbalance_machining_n: u_c,
            unbalance_measuring_n: u_m,
        }
    }

    /// The ranges of the fields: `(field, value, low, high)` of the first out of range.
    pub fn out_of_range(&self) -> Option<(&'static str, f64, f64, f64)> {
        [
            ("spindle_path.span_mm", self.span_mm, 1.0, 5000.0),
            ("spindle_path.overhang_mm", self.overhang_mm, 0.0, 5000.0),
            (
                "spindle_path.front_stiffness_n_per_um",
                self.front_stiffness_n_per_um,
                1.0,
                1e5,
            ),
            (
                "spindle_path.rear_stiffness_n_per_um",
                self.rear_stiffness_n_per_um,
                1.0,
                1e5,
            ),
            ("spindle_path.clearance_um", self.clearance_um, 0.0, 100.0),
            (
                "spindle_path.cutting_force_n",
                self.cutting_force_n,
                0.0,
                1e5,
            ),
            ("spindle_path.belt_load_n", self.belt_load_n, -1e5, 1e5),
            ("spindle_path.unbalance_g_mm", self.unbalance_g_mm, 0.0, 1e6),
            (
                "spindle_path.unbalance_phase_rad",
                self.unbalance_phase_rad,
                -1e3,
                1e3,
            ),
            ("spindle_path.machining_rpm", self.machining_rpm, 0.0, 1e6),
        ]
        .into_iter()
        .find(|&(_, v, lo, hi)| !(lo..=hi).contains(&v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The typical supports with no play and only `cutting_force_n` of load.
    fn only_cutting_force(cutting_force_n: f64) -> SpindlePath {
        SpindlePath {
            clearance_um: 0.0,
            cutting_force_n,
            belt_load_n: 0.0,
            unbalance_g_mm: 0.0,
            ..SpindlePath::typical()
        }
    }

    #[test]
    fn no_loads_no_difference() {
        assert!(only_cutting_force(0.0).difference(800.0).is_zero());
        let d = SpindlePath::none().difference(800.0);
        assert_eq!(d.offset_um, 0.0);
        assert_eq!(d.first_harmonic.amplitude_um, 0.0);
    }

    #[test]
    fn cutting_force_alone_is_its_deflection_at_the_section() {
        // Worked by hand: a = 120, b = 300: levers 1.4 and 0.4; compliance at the section
        // 1.4²/500 + 0.4²/200 = 0.00472 µm/N; F_p 25 N: 0.118 µm, the part read larger.
        let d = only_cutting_force(25.0).difference(800.0);
        assert!((d.offset_um - 0.118).abs() < 1e-9, "{d:?}");
    }

    #[test]
    fn the_default_is_the_typical_lathe() {
        assert_eq!(SpindlePath::default(), SpindlePath::typical());
        assert!(!SpindlePath::default().difference(800.0).is_zero());
    }

    #[test]
    fn typical_rig_clearance_dominates() {
        // Machining: the front support holds 25·1.4 = 35 N against 13.2·1.4 = 18.4 N
        // rotating, so the clearance is taken up (−2 µm at the front); measuring at
        // 800 rpm only 8.4·1.4 = 11.8 N rotates and nothing holds the front journal: it
        // orbits. The rear is held by the belt in both states.
        let d = SpindlePath::typical().difference(800.0);
        assert!((d.unbalance_machining_n - 13.16).abs() < 0.01, "{d:?}");
        let front = 1.4;
        let offset = 2.0 * front + 25.0 * (1.4f64.powi(2) / 500.0 + 0.4f64.powi(2) / 200.0);
        assert!((d.offset_um - offset).abs() < 1e-6, "{d:?}");
        // The orbit: 2 µm of play × 1.4 at the front, less the held machining deflection.
        assert!((2.7..2.8).contains(&d.first_harmonic.amplitude_um), "{d:?}");
    }
}
