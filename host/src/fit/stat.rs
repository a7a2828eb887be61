//! The statistics a fit compares: what `analyze` computes of a record, by name, and which
//! of them a fit weighs by default.

use stickslip_model::rig::ACCEL_NAMES;

use crate::recorded::analysis::Analysis;

/// One statistic of a record. Per channel: peak-to-peak, RMS, groan-band RMS [m/s^2], the
/// spectral peak [Hz]; per case: the estimator's stick fraction [-], stick-slip frequency
/// [Hz] and the time of its first slip onset in the record [s].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Stat {
    Pp,
    Rms,
    GroanRms,
    PeakHz,
    StickFraction,
    StickSlipHz,
    FirstSlipS,
}

impl Stat {
    pub const ALL: [Stat; 7] =
        [Stat::Pp, Stat::Rms, Stat::GroanRms, Stat::PeakHz, Stat::StickFraction, Stat::StickSlipHz, Stat::FirstSlipS];

    /// The name in tables, JSON and `--weights`.
    pub fn name(self) -> &'static str {
        match self {
            Stat::Pp => "pp",
            Stat::Rms => "rms",
            Stat::GroanRms => "groan_rms",
            Stat::PeakHz => "peak_hz",
            Stat::StickFraction => "stick_fraction",
            Stat::StickSlipHz => "stick_slip_hz",
            Stat::FirstSlipS => "first_slip_s",
        }
    }

    pub fn unit(self) -> &'static str {
        match self {
            Stat::Pp | Stat::Rms | Stat::GroanRms => "m/s^2",
            Stat::PeakHz | Stat::StickSlipHz => "Hz",
            Stat::StickFraction => "-",
            Stat::FirstSlipS => "s",
        }
    }

    pub fn parse(s: &str) -> Option<Stat> {
        Stat::ALL.into_iter().find(|k| k.name() == s)
    }

    /// Whether the statistic belongs to a channel (else to the case).
    pub fn per_channel(self) -> bool {
        matches!(self, Stat::Pp | Stat::Rms | Stat::GroanRms | Stat::PeakHz)
    }

    /// The default weight of its log ratio in a fit. The spectral peak is good to one Welch
    /// bin only (a step function of the parameters), so it is left out unless weighted.
    pub fn default_weight(self) -> f64 {
        match self {
            Stat::PeakHz => 0.0,
            _ => 1.0,
        }
    }

    /// Its value in `a` (`channel` for a per-channel statistic); `None` where the analysis
    /// has none (no spectrum, fewer than two slip onsets, no onset).
    pub fn of(self, a: &Analysis, channel: Option<usize>) -> Option<f64> {
        let ch = |c: Option<usize>| c.map(|c| &a.channels[c]);
        match self {
            Stat::Pp => ch(channel).map(|c| c.pp),
            Stat::Rms => ch(channel).map(|c| c.rms),
            Stat::GroanRms => ch(channel).map(|c| c.groan_rms),
            Stat::PeakHz => ch(channel).and_then(|c| c.peak_hz),
            Stat::StickFraction => Some(a.stick_fraction),
            Stat::StickSlipHz => a.stick_slip_hz,
            Stat::FirstSlipS => a.first_onset_s,
        }
    }
}

/// A channel by name (`disc_x`, `pad_x`, `pad_trail`, `pad_lead`).
pub fn channel_index(name: &str) -> Option<usize> {
    ACCEL_NAMES.iter().position(|n| *n == name)
}

/// Which statistic of which case: the key of a measured value and of its model value.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct StatKey {
    pub case: String,
    /// `None` for a per-case statistic.
    pub channel: Option<usize>,
    pub stat: Stat,
}

impl StatKey {
    pub fn channel_name(&self) -> &'static str {
        self.channel.map_or("", |c| ACCEL_NAMES[c])
    }

    /// "pull_center pad_x pp", for messages.
    pub fn label(&self) -> String {
        match self.channel {
            Some(c) => format!("{} {} {}", self.case, ACCEL_NAMES[c], self.stat.name()),
            None => format!("{} {}", self.case, self.stat.name()),
        }
    }
}

/// Every statistic key of a case a recording gives, channels first.
pub fn recording_keys(case: &str) -> Vec<StatKey> {
    let mut v = Vec::new();
    for stat in Stat::ALL {
        if stat.per_channel() {
            for c in 0..ACCEL_NAMES.len() {
                v.push(StatKey { case: case.to_string(), channel: Some(c), stat });
            }
        } else {
            v.push(StatKey { case: case.to_string(), channel: None, stat });
        }
    }
    v
}
