//! The spindle-drive sampling chain (docs/domain.md §3): 1 kHz ADC codes, a first-order low-pass
//! near 100 Hz, and a boxcar average over each control period (h = 0.05 s at 20 Hz).
//!
//! Why this shape: the phase voltages and currents are sinusoids at the electrical frequency
//! (tens of Hz), so they cannot be low-passed themselves. The chain therefore squares them
//! per sample first — for a balanced three-phase set, Σv² and Σi² are constant, so
//! `V_line = √(Σv²/3)` (eq. F3, docs/domain.md) is exact at every sample — and filters the squares.
//! Speed, measured power and the dynamometer force are filtered as they are.
//!
//! ## Formats
//! - ADC codes: 12 bit, `0..=4095` (larger codes are clamped to 4095). Speed and measured
//!   power are unipolar (code × scale); phase voltages, phase currents and the dynamometer
//!   force are bipolar around [`ADC_MID`] ((code − 2048) × scale). `i_w = −i_u − i_v`.
//! - Channel order: [`AdcChannel::ALL`] (speed, power, force, v_u, v_v, v_w, i_u, i_v), the
//!   one order of a sample as an array ([`AdcCodes::to_array`]) everywhere outside the model.
//! - Filter state and averages: `i64` in codes (or codes² for the squares) with
//!   [`FILTER_FRAC_BITS`] fractional bits. Largest magnitude: Σi² ≤ 2·2048² + 4095² < 2^25,
//!   ×2^8 < 2^33, summed over at most 1000 samples < 2^43: no `i64` operation here can
//!   overflow, and every one is still written saturating.
//! - Low-pass: `y ← y + (x·2^8 − y) >> k` (arithmetic shift, rounds toward −∞), one step per
//!   sample; `k = lowpass_shift`. Its −3 dB frequency is `−ln(1 − 2^−k)·f_s / 2π`: k = 1 gives
//!   110 Hz at 1 kHz — the "100 Hz low-pass" of docs/domain.md §3.
//! - Average: the filter outputs of the samples since the previous control tick are summed
//!   and divided by their number (integer division, rounding toward zero). A tick with no
//!   sample repeats the previous averages.
//! - Physical units: [`AdcScales::convert`] turns a period's averages into
//!   [`DriveSignals`] (I32F32, SI units), the estimator's input.

use crate::units::{Amps, Fx, Newtons, RadPerSec, Volts, Watts};

/// Mid-scale code of the bipolar channels.
pub const ADC_MID: i32 = 2048;
/// Largest ADC code.
pub const ADC_MAX: u16 = 4095;
/// Fractional bits of the filter state and of [`Averages`].
pub const FILTER_FRAC_BITS: u32 = 8;

/// One 1 kHz sample of every spindle-drive channel, raw 12-bit ADC codes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct AdcCodes {
    /// Motor speed ω_M, unipolar: rad/s = code × `speed_per_lsb`.
    pub speed: u16,
    /// Measured (lagging) drive power P_o, unipolar: W = code × `power_per_lsb`.
    pub power: u16,
    /// Dynamometer cutting force, bipolar: N = (code − 2048) × `force_per_lsb`.
    pub force: u16,
    /// Phase voltages v_u, v_v, v_w, bipolar: V = (code − 2048) × `volts_per_lsb`.
    pub volts: [u16; 3],
    /// Phase currents i_u, i_v, bipolar: A = (code − 2048) × `amps_per_lsb`.
    pub amps: [u16; 2],
}

/// One ADC channel of the spindle drive. [`AdcChannel::ALL`] is the one order of the eight
/// channels: the sample record's payload, the Python rows, the HAL component's `adc-*` pins
/// and the Nucleo's conversion order all follow it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AdcChannel {
    /// Motor speed ω_M ([`AdcCodes::speed`]).
    Speed,
    /// Measured drive power P_o ([`AdcCodes::power`]).
    Power,
    /// Dynamometer force ([`AdcCodes::force`]).
    Force,
    /// Phase voltage v_u (`AdcCodes::volts[0]`).
    VoltsU,
    /// Phase voltage v_v (`AdcCodes::volts[1]`).
    VoltsV,
    /// Phase voltage v_w (`AdcCodes::volts[2]`).
    VoltsW,
    /// Phase current i_u (`AdcCodes::amps[0]`).
    AmpsU,
    /// Phase current i_v (`AdcCodes::amps[1]`).
    AmpsV,
}

impl AdcChannel {
    /// Number of ADC channels in one sample.
    pub const COUNT: usize = 8;

    /// Every channel, in sample order (index `i` is the channel whose
    /// [`AdcChannel::index`] is `i`).
    pub const ALL: [AdcChannel; AdcChannel::COUNT] = [
        AdcChannel::Speed,
        AdcChannel::Power,
        AdcChannel::Force,
        AdcChannel::VoltsU,
        AdcChannel::VoltsV,
        AdcChannel::VoltsW,
        AdcChannel::AmpsU,
        AdcChannel::AmpsV,
    ];

    /// The channel's position in [`AdcChannel::ALL`] (and in a sample's array form).
    pub const fn index(self) -> usize {
        let mut i = 0;
        while i < AdcChannel::COUNT {
            if AdcChannel::ALL[i] as u8 == self as u8 {
                return i;
            }
            i += 1;
        }
        panic!("every channel is in AdcChannel::ALL")
    }

    /// The channel's name, snake case: `speed`, `power`, `force`, `volts_u`, `volts_v`,
    /// `volts_w`, `amps_u`, `amps_v` (the HAL pins are `adc-` and this, with dashes).
    pub const fn name(self) -> &'static str {
        match self {
            AdcChannel::Speed => "speed",
            AdcChannel::Power => "power",
            AdcChannel::Force => "force",
            AdcChannel::VoltsU => "volts_u",
            AdcChannel::VoltsV => "volts_v",
            AdcChannel::VoltsW => "volts_w",
            AdcChannel::AmpsU => "amps_u",
            AdcChannel::AmpsV => "amps_v",
        }
    }

    /// The [`AdcCodes`] field that holds the channel, as written in Rust and in C
    /// (the C ABI's `TtAdcCodes` has the same fields): `speed`, `volts[0]`, `amps[1]`, ...
    pub const fn field(self) -> &'static str {
        match self {
            AdcChannel::Speed => "speed",
            AdcChannel::Power => "power",
            AdcChannel::Force => "force",
            AdcChannel::VoltsU => "volts[0]",
            AdcChannel::VoltsV => "volts[1]",
            AdcChannel::VoltsW => "volts[2]",
            AdcChannel::AmpsU => "amps[0]",
            AdcChannel::AmpsV => "amps[1]",
        }
    }

    /// What the channel measures, in words (`motor speed`, `phase current u`, ...).
    pub const fn quantity(self) -> &'static str {
        match self {
            AdcChannel::Speed => "motor speed",
            AdcChannel::Power => "drive power",
            AdcChannel::Force => "dynamometer force",
            AdcChannel::VoltsU => "phase voltage u",
            AdcChannel::VoltsV => "phase voltage v",
            AdcChannel::VoltsW => "phase voltage w",
            AdcChannel::AmpsU => "phase current u",
            AdcChannel::AmpsV => "phase current v",
        }
    }

    /// Bipolar around [`ADC_MID`] (force, phase voltages and currents) or unipolar
    /// (speed, power).
    pub const fn bipolar(self) -> bool {
        !matches!(self, AdcChannel::Speed | AdcChannel::Power)
    }
}

impl AdcCodes {
    /// The codes in [`AdcChannel::ALL`] order.
    pub fn to_array(&self) -> [u16; AdcChannel::COUNT] {
        AdcChannel::ALL.map(|ch| self[ch])
    }

    /// Codes from an array in [`AdcChannel::ALL`] order.
    pub fn from_array(codes: [u16; AdcChannel::COUNT]) -> AdcCodes {
        let mut c = AdcCodes::default();
        for (ch, code) in AdcChannel::ALL.into_iter().zip(codes) {
            c[ch] = code;
        }
        c
    }
}

impl core::ops::Index<AdcChannel> for AdcCodes {
    type Output = u16;
    fn index(&self, ch: AdcChannel) -> &u16 {
        match ch {
            AdcChannel::Speed => &self.speed,
            AdcChannel::Power => &self.power,
            AdcChannel::Force => &self.force,
            AdcChannel::VoltsU => &self.volts[0],
            AdcChannel::VoltsV => &self.volts[1],
            AdcChannel::VoltsW => &self.volts[2],
            AdcChannel::AmpsU => &self.amps[0],
            AdcChannel::AmpsV => &self.amps[1],
        }
    }
}

impl core::ops::IndexMut<AdcChannel> for AdcCodes {
    fn index_mut(&mut self, ch: AdcChannel) -> &mut u16 {
        match ch {
            AdcChannel::Speed => &mut self.speed,
            AdcChannel::Power => &mut self.power,
            AdcChannel::Force => &mut self.force,
            AdcChannel::VoltsU => &mut self.volts[0],
            AdcChannel::VoltsV => &mut self.volts[1],
            AdcChannel::VoltsW => &mut self.volts[2],
            AdcChannel::AmpsU => &mut self.amps[0],
            AdcChannel::AmpsV => &mut self.amps[1],
        }
    }
}

/// Number of filtered channels.
pub const CHANNELS: usize = 5;

/// Per-period averages of the filtered channels, codes with [`FILTER_FRAC_BITS`] fraction
/// bits (`Σv²` and `Σi²` in codes²).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Averages {
    /// Speed, codes.
    pub speed: i64,
    /// Measured power, codes.
    pub power: i64,
    /// Dynamometer force, codes relative to mid-scale.
    pub force: i64,
    /// v_u² + v_v² + v_w², codes².
    pub volts_sq: i64,
    /// i_u² + i_v² + i_w², codes².
    pub amps_sq: i64,
    /// Samples averaged (0 when the tick repeated the previous averages).
    pub samples: u16,
}

/// The sampling chain's state: one low-pass per channel and the period's running sums.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Sampler {
    shift: u32,
    filtered: [i64; CHANNELS],
    sums: [i64; CHANNELS],
    count: u16,
    primed: bool,
    last: Averages,
}

fn code(c: u16) -> i64 {
    i64::from(c.min(ADC_MAX))
}

fn centered(c: u16) -> i64 {
    code(c).saturating_sub(i64::from(ADC_MID))
}

impl Sampler {
    /// A sampler whose low-pass has coefficient `2^-lowpass_shift` (`1..=8`, validated by
    /// the force configuration; larger values are clamped to 8).
    pub fn new(lowpass_shift: u8) -> Sampler {
        Sampler {
            shift: u32::from(lowpass_shift.clamp(1, 8)),
            ..Sampler::default()
        }
    }

    /// One ADC sample: square the phase signals, low-pass every channel, add to the
    /// period's sums. The first sample after construction loads the filters directly (no
    /// start-up transient). Saturating throughout (cannot saturate; see the module header).
    pub fn on_sample(&mut self, adc: &AdcCodes) {
        let [vu, vv, vw] = adc.volts.map(centered);
        let [iu, iv] = adc.amps.map(centered);
        let iw = iu.saturating_add(iv).saturating_neg();
        let sq = |a: i64, b: i64, c: i64| {
            a.saturating_mul(a)
                .saturating_add(b.saturating_mul(b))
                .saturating_add(c.saturating_mul(c))
        };
        let x = [
            code(adc.speed),
            code(adc.power),
            centered(adc.force),
            sq(vu, vv, vw),
            sq(iu, iv, iw),
        ];
        for ((y, s), x) in self.filtered.iter_mut().zip(self.sums.iter_mut()).zip(x) {
            let target = x.saturating_mul(1 << FILTER_FRAC_BITS);
            if self.primed {
                *y = y.saturating_add(target.saturating_sub(*y) >> self.shift);
            } else {
                *y = target;
            }
            *s = s.saturating_add(*y);
        }
        self.primed = true;
        self.count = self.count.saturating_add(1);
    }

    /// Control tick: the averages of the samples since the previous tick; the sums restart.
    /// With no sample in the period the previous averages are returned with `samples = 0`.
    pub fn on_tick(&mut self) -> Averages {
        let n = i64::from(self.count);
        let avg = |s: i64| s.checked_div(n);
        let [speed, power, force, volts_sq, amps_sq] = self.sums.map(avg);
        match (speed, power, force, volts_sq, amps_sq) {
            (Some(speed), Some(power), Some(force), Some(volts_sq), Some(amps_sq)) => {
                self.last = Averages {
                    speed,
                    power,
                    force,
                    volts_sq,
                    amps_sq,
                    samples: self.count,
                };
            }
            _ => self.last.samples = 0,
        }
        self.sums = [0; CHANNELS];
        self.count = 0;
        self.last
    }
}

#[cfg(feature = "internals")]
impl crate::internals::Internals for Sampler {
    /// Per channel (`speed`, `power`, `force`, `volts_sq`, `amps_sq`): the low-pass state
    /// `sampler.filtered[ch]`, the period's running sum `sampler.sums[ch]` and the last
    /// period's average `sampler.average[ch]` (`i64` with [`FILTER_FRAC_BITS`] fractional
    /// bits, I56F8, saturating); then the period's sample count `sampler.count` (`u16`).
    fn internals(&self, f: &mut dyn FnMut(crate::internals::Register)) {
        use crate::internals::{Format, Register};
        const FILTERED: [&str; CHANNELS] = [
            "sampler.filtered[speed]",
            "sampler.filtered[power]",
            "sampler.filtered[force]",
            "sampler.filtered[volts_sq]",
            "sampler.filtered[amps_sq]",
        ];
        const SUMS: [&str; CHANNELS] = [
            "sampler.sums[speed]",
            "sampler.sums[power]",
            "sampler.sums[force]",
            "sampler.sums[volts_sq]",
            "sampler.sums[amps_sq]",
        ];
        const AVERAGE: [&str; CHANNELS] = [
            "sampler.average[speed]",
            "sampler.average[power]",
            "sampler.average[force]",
            "sampler.average[volts_sq]",
            "sampler.average[amps_sq]",
        ];
        let q8 = Format::fixed(64, FILTER_FRAC_BITS as u8);
        let l = &self.last;
        let average = [l.speed, l.power, l.force, l.volts_sq, l.amps_sq];
        for (names, values) in [
            (&FILTERED, &self.filtered),
            (&SUMS, &self.sums),
            (&AVERAGE, &average),
        ] {
            for (name, &v) in names.iter().zip(values.iter()) {
                f(Register::new(name, q8, v.into()));
            }
        }
        f(Register::new(
            "sampler.count",
            Format::unsigned(16),
            self.count.into(),
        ));
    }
}

/// ADC scales of the sampling chain (docs/domain.md §3), I32F32 units per LSB.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AdcScales {
    /// Motor speed per LSB, rad/s, `(0, 1]`.
    pub speed_per_lsb: RadPerSec,
    /// Measured power per LSB, W, `(0, 100]`.
    pub power_per_lsb: Watts,
    /// Dynamometer force per LSB, N, `(0, 100]`.
    pub force_per_lsb: Newtons,
    /// Phase voltage per LSB, V, `(0, 10]`.
    pub volts_per_lsb: Volts,
    /// Phase current per LSB, A, `(0, 1]`.
    pub amps_per_lsb: Amps,
}

impl Default for AdcScales {
    /// The default plant's channels (`tooltouch control`): 0.05 rad/s, 2.5 W, 1 N, 0.25 V
    /// and 5 mA per LSB.
    fn default() -> Self {
        AdcScales {
            speed_per_lsb: const { Fx::lit("0.05") },
            power_per_lsb: const { Fx::lit("2.5") },
            force_per_lsb: Fx::ONE,
            volts_per_lsb: const { Fx::lit("0.25") },
            amps_per_lsb: const { Fx::lit("0.005") },
        }
    }
}

/// The period's averaged signals in physical units.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DriveSignals {
    /// Motor speed ω_M, rad/s.
    pub omega: RadPerSec,
    /// Measured (lagging) power P_o, W.
    pub p_o: Watts,
    /// Dynamometer force, N.
    pub force_measured: Newtons,
    /// Line voltage V_line = √(Σv²/3), V.
    pub v_line: Volts,
    /// Line current I_line = √(Σi²/3), A.
    pub i_line: Amps,
    /// Σi² = i_u² + i_v² + i_w², A².
    pub amps_sq: Fx,
}

fn code_to_fx(avg: i64) -> Fx {
    // avg has FILTER_FRAC_BITS fractional bits; I32F32 has 32. Saturating shift by multiply.
    Fx::from_bits(avg.saturating_mul(1 << (32 - FILTER_FRAC_BITS)))
}

fn rms_of_sum3(avg_sq: i64) -> Fx {
    // √(x/3) with x = avg·2^−8: bits = √(avg·2^56/3). avg ≥ 0 and < 2^34, so this fits.
    let avg = u128::try_from(avg_sq).unwrap_or(0);
    let root = ((avg << (64 - FILTER_FRAC_BITS)) / 3).isqrt();
    Fx::from_bits(i64::try_from(root).unwrap_or(i64::MAX))
}

impl AdcScales {
    /// Converts the period's averages to physical units (saturating products).
    pub fn convert(&self, a: &Averages) -> DriveSignals {
        DriveSignals {
            omega: code_to_fx(a.speed).saturating_mul(self.speed_per_lsb),
            p_o: code_to_fx(a.power).saturating_mul(self.power_per_lsb),
            force_measured: code_to_fx(a.force).saturating_mul(self.force_per_lsb),
            v_line: rms_of_sum3(a.volts_sq).saturating_mul(self.volts_per_lsb),
            i_line: rms_of_sum3(a.amps_sq).saturating_mul(self.amps_per_lsb),
            amps_sq: code_to_fx(a.amps_sq)
                .saturating_mul(self.amps_per_lsb)
                .saturating_mul(self.amps_per_lsb),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_channel_order_is_the_sample_order() {
        let codes = AdcCodes {
            speed: 1,
            power: 2,
            force: 3,
            volts: [4, 5, 6],
            amps: [7, 8],
        };
        assert_eq!(codes.to_array(), [1, 2, 3, 4, 5, 6, 7, 8]);
        assert_eq!(AdcCodes::from_array(codes.to_array()), codes);
        for (i, ch) in AdcChannel::ALL.into_iter().enumerate() {
            assert_eq!(ch.index(), i);
        }
        assert_eq!(
            AdcChannel::ALL.map(AdcChannel::name),
            ["speed", "power", "force", "volts_u", "volts_v", "volts_w", "amps_u", "amps_v"]
        );
        assert_eq!(
            AdcChannel::ALL.map(AdcChannel::field),
            ["speed", "power", "force", "volts[0]", "volts[1]", "volts[2]", "amps[0]", "amps[1]"]
        );
        assert_eq!(codes[AdcChannel::AmpsU], codes.amps[0]);
        assert!(AdcChannel::Force.bipolar() && !AdcChannel::Power.bipolar());
    }

    #[test]
    fn constant_codes_average_to_themselves() {
        let mut s = Sampler::new(1);
        let adc = AdcCodes {
            speed: 1000,
            power: 500,
            force: 2048 + 100,
            volts: [2048 + 3, 2048 - 4, 2048],
            amps: [2048 + 1, 2048 + 2],
        };
        for _ in 0..50 {
            s.on_sample(&adc);
        }
        let a = s.on_tick();
        assert_eq!(a.speed, 1000 << 8);
        assert_eq!(a.power, 500 << 8);
        assert_eq!(a.force, 100 << 8);
        assert_eq!(a.volts_sq, 25 << 8);
        assert_eq!(a.amps_sq, (1 + 4 + 9) << 8);
        assert_eq!(a.samples, 50);
        let b = s.on_tick();
        assert_eq!(b.samples, 0);
        assert_eq!(b.speed, a.speed);
    }

    #[test]
    fn four_samples_by_hand() {
        // Shift 2: y = 0 (primed), then y += (400·256 − y)/4: 25600, 44800, 59200; mean
        // (0 + 25600 + 44800 + 59200) / 4 = 32400.
        let mut s = Sampler::new(2);
        for speed in [0, 400, 400, 400] {
            s.on_sample(&AdcCodes {
                speed,
                ..AdcCodes::default()
            });
        }
        let a = s.on_tick();
        assert_eq!((a.speed, a.samples), (32400, 4));
        // One more sample of 400: 59200 + 10800 = 70000, alone in its period.
        s.on_sample(&AdcCodes {
            speed: 400,
            ..AdcCodes::default()
        });
        assert_eq!(s.on_tick().speed, 70000);
    }

    #[test]
    fn phase_squares_and_the_third_current() {
        // v = +100, −50, −50 codes: Σv² = 15000; i_u = 10, i_v = −4, so i_w = −6:
        // Σi² = 100 + 16 + 36 = 152; codes above 4095 read as 4095.
        let mut s = Sampler::new(3);
        s.on_sample(&AdcCodes {
            speed: 5000,
            power: 7,
            force: 2048 - 9,
            volts: [2148, 1998, 1998],
            amps: [2058, 2044],
        });
        let a = s.on_tick();
        assert_eq!(
            (a.speed, a.power, a.force, a.volts_sq, a.amps_sq),
            (4095 << 8, 7 << 8, -9 << 8, 15000 << 8, 152 << 8)
        );
    }

    #[test]
    fn the_shift_is_clamped_to_1_through_8() {
        let step = |shift: u8| {
            let mut s = Sampler::new(shift);
            s.on_sample(&AdcCodes::default());
            s.on_tick();
            s.on_sample(&AdcCodes {
                speed: 1024,
                ..AdcCodes::default()
            });
            s.on_tick().speed
        };
        // One step from 0 toward 1024·256 = 262144: >> 1 = 131072, >> 8 = 1024.
        assert_eq!(step(0), 131_072);
        assert_eq!(step(1), 131_072);
        assert_eq!(step(8), 1024);
        assert_eq!(step(200), 1024);
    }

    #[test]
    fn averages_convert_to_physical_units() {
        let scales = AdcScales {
            speed_per_lsb: Fx::lit("0.125"),
            power_per_lsb: Fx::const_from_int(2),
            force_per_lsb: Fx::ONE,
            volts_per_lsb: Fx::lit("0.25"),
            amps_per_lsb: Fx::lit("0.0625"),
        };
        let a = Averages {
            speed: 400 << 8,
            power: 1000 << 8,
            force: -100 << 8,
            volts_sq: (3 * 100 * 100) << 8,
            amps_sq: (3 * 16 * 16) << 8,
            samples: 1,
        };
        let d = scales.convert(&a);
        // 400/8 rad/s, 2000 W, −100 N, √(30000/3)·0.25 = 25 V, √(768/3)/16 = 1 A,
        // Σi² = 768/256 = 3 A².
        assert_eq!(
            (
                d.omega,
                d.p_o,
                d.force_measured,
                d.v_line,
                d.i_line,
                d.amps_sq
            ),
            (
                Fx::const_from_int(50),
                Fx::const_from_int(2000),
                Fx::const_from_int(-100),
                Fx::const_from_int(25),
                Fx::ONE,
                Fx::const_from_int(3)
            )
        );
    }

    #[test]
    fn lowpass_follows_a_step() {
        let mut s = Sampler::new(1);
        s.on_sample(&AdcCodes::default());
        let _ = s.on_tick();
        for _ in 0..50 {
            s.on_sample(&AdcCodes {
                speed: 4095,
                ..AdcCodes::default()
            });
        }
        let a = s.on_tick();
        // y_k = 4095·(1 − 2^−k): the period's mean loses Σ2^−k ≈ 1 sample of 50, ~82 codes
        assert!(a.speed > 4010 << 8 && a.speed < 4016 << 8, "{}", a.speed);
    }
}
