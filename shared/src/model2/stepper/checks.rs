//! The checks after each chunk: finite, in range, in contact, the band within its range; the
//! halt's classification out of line.

use super::*;

impl<T: Real, C: Composition> Model2Tables<T, C> {
    /// Finite, in range, in contact; the band within its range. The common case is one
    /// branch; the halt's classification (and its time, in f64) is out of line.
    #[inline(always)]
    pub(super) fn check(&self, s: &Model2State<T>, z: &[T; NS], regime: Regime, sub: u32, unit: u64) -> Result<(), Halt> {
        if self.in_range(z) {
            return Ok(());
        }
        self.check_failed(s, z, regime, sub, unit)
    }

    /// Whether `z` passes [`Self::check`] (false for any NaN).
    #[inline(always)]
    pub(super) fn in_range(&self, z: &[T; NS]) -> bool {
        let pad = [z[0], z[1], z[2], z[3]];
        let band_ok = !C::BAND || ((z[4].abs() <= self.u_limit) & (z[5].abs() <= self.udot_limit));
        self.limits.in_range(&pad) & band_ok & self.float_ok(z)
    }

    /// The floating pad: both contact springs compressed (y + d phi >= 0, to round-off), y and
    /// y' in range. Always true for a hinged pad.
    #[inline(always)]
    pub(super) fn float_ok(&self, z: &[T; NS]) -> bool {
        if !C::FLOAT {
            return true;
        }
        let [d_l, d_t, floor_l, floor_t, y_limit, ydot_limit] = self.float_limits;
        (z[Y] + d_l * z[2] >= floor_l) & (z[Y] + d_t * z[2] >= floor_t) & (z[Y].abs() <= y_limit) & (z[Y + 1].abs() <= ydot_limit)
    }

    #[cold]
    #[inline(never)]
    pub(super) fn check_failed(&self, s: &Model2State<T>, z: &[T; NS], regime: Regime, sub: u32, unit: u64) -> Result<(), Halt> {
        let pad = [z[0], z[1], z[2], z[3]];
        self.limits.check(&pad, regime, || self.time_at(s, sub, unit))?;
        if C::FLOAT && !self.float_ok(z) {
            let t = self.time_at(s, sub, unit);
            if !(z[Y].is_finite() && z[Y + 1].is_finite()) {
                return Err(Halt::NonFinite { t });
            }
            let [d_l, d_t, floor_l, floor_t, _, _] = self.float_limits;
            let (y, phi) = (z[Y].to_f64(), z[2].to_f64());
            if !(z[Y] + d_l * z[2] >= floor_l) {
                return Err(Halt::ContactLoss { t, n: self.springs[0] * (y + self.springs[1] * phi) });
            }
            if !(z[Y] + d_t * z[2] >= floor_t) {
                return Err(Halt::ContactLoss { t, n: self.springs[2] * (y + self.springs[3] * phi) });
            }
            return Err(Halt::Diverged { t, regime, stiffness_margin: self.limits.margins[regime.index()] });
        }
        if C::BAND && (!(z[4].abs() <= self.u_limit) || !(z[5].abs() <= self.udot_limit)) {
            let t = self.time_at(s, sub, unit);
            if !(z[4].is_finite() && z[5].is_finite()) {
                return Err(Halt::NonFinite { t });
            }
            return Err(Halt::Diverged { t, regime, stiffness_margin: self.limits.margins[regime.index()] });
        }
        Ok(())
    }
}
