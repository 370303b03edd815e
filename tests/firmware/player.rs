//! The lathe player's image executed: its `emulated` build under QEMU's netduinoplus2
//! plays the demo stream once and records every GPIOC_BSRR write with the TIM2 tick its
//! loop saw (`tooltouch_firmware_runner::player`). The recording must be the schedule the host makes
//! for the same stream and rate (`tooltouch_firmware::player::Schedule`, its source compiled
//! into `tooltouch_firmware_runner::player`; the firmware's host tests check it against the stream's events), word for word
//! and in order,
//! each write at or after its tick, within [`SPIN_TICKS`] of it when the loop was free and
//! within [`STEP_TICKS`] of the write before it when that one was still going out; the run
//! must cross TIM2's 32-bit wrap (the image starts each run just before it) and its log
//! must report the figures the recording gives.
//!
//! Needs qemu-system-arm and the thumbv7em-none-eabihf target: without them the test
//! fails with a message naming `cargo xtask setup`.

use tooltouch_firmware_runner::player::firmware_player::{
    Schedule, Step, NUCLEO_PINS, WRAP_AHEAD_TICKS,
};
use tooltouch_firmware_runner::player::{self, exit_code, EMULATED_TIMER_HZ};

/// Ticks of 500 MHz (2 instructions each under `-icount shift=0`) the loop may take to
/// see a step due once it spins for it: one spin iteration, measured 0–3 ticks.
const SPIN_TICKS: u64 = 8;
/// Ticks of one step of the loop, from one BSRR write to the next when the second is
/// already due: the schedule decoding the next record, the write and its recording,
/// measured 205–209 ticks (410–418 instructions). A step of the same tick as the one
/// before it (index and FES together, a contact edge on an FES edge) goes out this much
/// after it.
const STEP_TICKS: u64 = 256;

#[test]
fn the_player_image_plays_the_host_schedule_under_netduinoplus2() {
    let image = player::build_emulated().unwrap_or_else(|e| panic!("{e}"));
    let run = player::run_emulated(&image).unwrap_or_else(|e| panic!("{e}"));
    let log = run.log.join("\n");
    assert_eq!(
        run.status,
        Some(i32::from(exit_code::PLAYED)),
        "QEMU's exit status; the log:\n{log}"
    );

    let stream =
        std::fs::read(tooltouch_firmware_runner::qemu::firmware_dir().join("tooltouch-events.bin"))
            .unwrap();
    let (header, summary, schedule) =
        Schedule::new(&stream, EMULATED_TIMER_HZ, NUCLEO_PINS).unwrap();
    let steps: Vec<Step> = schedule.collect();
    assert_eq!(
        run.writes.len(),
        steps.len(),
        "BSRR writes recorded vs the host schedule's steps"
    );
    let (mut worst, mut late, mut spin_worst) = (0, 0, 0);
    for (i, (w, s)) in run.writes.iter().zip(&steps).enumerate() {
        assert_eq!(
            w.bsrr, s.bsrr,
            "step {i} ({:?} at tick {}): the player wrote BSRR {:#010x}, the schedule has \
             {:#010x}",
            s.what, s.at, w.bsrr, s.bsrr
        );
        assert!(
            w.seen_at >= s.at,
            "step {i} ({:?}): written at tick {}, before its tick {}",
            s.what,
            w.seen_at,
            s.at
        );
        let lateness = w.seen_at - s.at;
        // Free: the previous write went out more than a step's time before this tick.
        let free_from = i
            .checked_sub(1)
            .map_or(0, |p| run.writes[p].seen_at + STEP_TICKS);
        let bound = s.at.max(free_from) + SPIN_TICKS;
        assert!(
            w.seen_at <= bound,
            "step {i} ({:?} at tick {}): written at tick {}, {lateness} ticks late, after \
             tick {bound} (the loop was free from tick {free_from})",
            s.what,
            s.at,
            w.seen_at
        );
        if s.at >= free_from {
            spin_worst = spin_worst.max(lateness);
        }
        worst = worst.max(lateness);
        if lateness > 0 && s.at > 0 {
            late += 1;
        }
    }
    // The run lasted past the wrap of TIM2's 32-bit count: the 64-bit extension carried.
    assert!(
        summary.end > u64::from(WRAP_AHEAD_TICKS),
        "the demo stream ({} ticks) ends before TIM2 wraps",
        summary.end
    );
    assert!(run.writes.last().unwrap().seen_at > u64::from(WRAP_AHEAD_TICKS));

    // The image's own log: the stream's summary at the emulated rate, and the run's figures.
    let played = format!(
        "player: played {} steps in {} ticks; {late} steps seen late, the worst by {worst} \
         ticks",
        steps.len(),
        summary.end
    );
    assert!(
        run.log.contains(&played),
        "no `{played}` in the log:\n{log}"
    );
    let summary_line = run
        .log
        .iter()
        .find(|l| l.starts_with("player: ") && l.ends_with("press B1 to play"))
        .unwrap_or_else(|| panic!("no summary line in the log:\n{log}"));
    for part in [
        format!("{} events", summary.events),
        format!("{} FES pulses", summary.fes_pulses),
        format!("{} index pulses", summary.index_pulses),
        format!("{} ticks at {EMULATED_TIMER_HZ} Hz", summary.end),
        format!("measure hash {:x}", header.measure_hash),
    ] {
        assert!(
            summary_line.contains(&part),
            "`{part}` not in `{summary_line}`"
        );
    }
    println!(
        "player under QEMU: {} BSRR writes equal to the host schedule, {late} late, the worst \
         by {worst} ticks of 500 MHz (waiting for the write before), {spin_worst} when the \
         loop was free; {:.2} s",
        run.writes.len(),
        run.elapsed.as_secs_f64()
    );
}
