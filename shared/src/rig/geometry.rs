//! Where the pad's two y accelerometers sit and which way they read: the geometry that both the
//! per-sample chain (the estimator's friction-face coefficient) and the simulation harness's
//! sensor model ([`crate::harness::sensor_model`]) use.

use super::{check, ConfigError};
use crate::scene::{Caliper, Scene};

/// Where the two y accelerometers sit on the pad, and which way they read.
///
/// Geometry (docs/model.md): the pad, length 2l, rotates by phi about the pivot at its supported
/// edge, at mid-thickness: the trailing edge for a push caliper, the leading edge for a pull
/// caliper. Positive phi compresses the contact springs, i.e. moves every point of the pad
/// toward the band by (distance from the pivot) * phi. A sensor at distance `u` from the
/// trailing edge (toward the leading edge) is at the lever arm
///
/// ```text
/// r = u        (push: pivot at the trailing edge)
/// r = 2 l - u  (pull: pivot at the leading edge)
/// ```
///
/// and, with y positive toward the band (the sense of the normal load), reads y'' = r phi''
/// (plus the pivot's own y'' for a pad that is not hinged, `Motion::normal_acceleration` of the sensor model)
/// (the centripetal term r phi'^2 along the pad is neglected, and not sensed in y). So the sign
/// is the same for both calipers; what the caliper changes is which edge is the pivot: the
/// sensor near the pivot sees a small signal. An accelerometer mounted with its base on the
/// backing plate reads positive *away* from the band: set `y_polarity` to -1 for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorGeometry {
    /// Position of the `pad_trail` accelerometer, from the trailing edge [m], in [0, 2 l].
    pub trail_from_trailing_edge_m: f64,
    /// Position of the `pad_lead` accelerometer, from the trailing edge [m], in [0, 2 l].
    pub lead_from_trailing_edge_m: f64,
    /// +1: the y accelerometers read positive toward the band; -1: away from it.
    pub y_polarity: f64,
}

impl SensorGeometry {
    /// 5 mm in from each edge of the 80 mm pad, reading positive toward the band.
    pub const RIG: SensorGeometry =
        SensorGeometry { trail_from_trailing_edge_m: 0.005, lead_from_trailing_edge_m: 0.075, y_polarity: 1.0 };

    /// Lever arms about the pivot of the trailing and leading sensors [m] for `scene`, times the
    /// polarity.
    pub fn arms(&self, scene: &Scene) -> Result<(f64, f64), ConfigError> {
        let two_l = 2.0 * scene.l;
        for (field, u) in [
            ("geometry.trail_from_trailing_edge_m", self.trail_from_trailing_edge_m),
            ("geometry.lead_from_trailing_edge_m", self.lead_from_trailing_edge_m),
        ] {
            check(u.is_finite() && u >= 0.0 && u <= two_l, field, "sensor must sit on the pad: 0 <= u <= 2 l", u)?;
        }
        check(
            self.y_polarity == 1.0 || self.y_polarity == -1.0,
            "geometry.y_polarity",
            "must be +1 or -1",
            self.y_polarity,
        )?;
        let arm = |u: f64| match scene.caliper {
            Caliper::Push => u,
            Caliper::Pull => two_l - u,
        };
        Ok((
            self.y_polarity * arm(self.trail_from_trailing_edge_m),
            self.y_polarity * arm(self.lead_from_trailing_edge_m),
        ))
    }
}
