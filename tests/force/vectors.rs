//! The vectors `tooltouch control --out` writes: an Events stream of force events and an
//! Outputs stream of the model's ForceOutputs, which a fresh kernel reproduces bit for bit
//! from the events alone; broken files are clear errors.

use std::process::Command;
use tooltouch_model::force::config::ForceSource;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceKernel;
use tooltouch_model::wire::force_chunks::ForceConfigAssembler;
use tooltouch_model::wire::force_event::decode_force_event;
use tooltouch_model::wire::force_outputs::decode_force_outputs;
use tooltouch_model::wire::{kind, Records, StreamKind, WireError};
use tooltouch_plant::drive::kienzle::KienzleProcess;
use tooltouch_plant::drive::scenario::{kienzle_settings, ControllerKind};

fn replay(events: &[u8], outputs: &[u8]) -> Result<usize, String> {
    // `control`'s default process is the nonlinear one, with the controllers designed on it
    let config = kienzle_settings(
        ControllerKind::Fuzzy,
        ForceSource::Estimated,
        &KienzleProcess::default(),
    )
    .validate()
    .unwrap();
    let (he, ev) = Records::new(events).map_err(|e| e.to_string())?;
    let (ho, out) = Records::new(outputs).map_err(|e| e.to_string())?;
    assert_eq!(he.stream, StreamKind::Events);
    assert_eq!(ho.stream, StreamKind::Outputs);
    assert_eq!(
        he.force_hash,
        config.hash(),
        "events made with another configuration"
    );
    assert_eq!(ho.force_hash, config.hash());
    // The events file carries its force configuration (chunk records first).
    let mut ev = ev.peekable();
    let mut assembler = ForceConfigAssembler::new();
    while let Some(Ok(rec)) =
        ev.next_if(|r| matches!(r, Ok(r) if r.kind == kind::FORCE_CONFIG_CHUNK))
    {
        assembler.push(rec.payload()).map_err(|e| e.to_string())?;
    }
    let carried = assembler.finish(he.force_hash).map_err(|e| e.to_string())?;
    assert_eq!(
        carried, config,
        "the events file carries the run's configuration"
    );
    let mut kernel = ForceKernel::new(&carried);
    let mut expected = out.filter(|r| !matches!(r, Ok(r) if r.kind == kind::END));
    let mut compared = 0;
    for (i, rec) in ev.enumerate() {
        let rec = rec.map_err(|e| e.to_string())?;
        if rec.kind == kind::END {
            break;
        }
        let event = decode_force_event(&rec, i)
            .map_err(|e| e.to_string())?
            .ok_or_else(|| format!("record {i}: not a force event (kind {:#x})", rec.kind))?;
        kernel.apply(event);
        if matches!(event, ForceEvent::Sample(_)) {
            continue;
        }
        let exp = expected
            .next()
            .ok_or("outputs stream ends early")?
            .map_err(|e| e.to_string())?;
        assert_eq!(exp.kind, kind::FORCE_OUTPUTS);
        let want = decode_force_outputs(exp.payload()).ok_or("bad outputs record")?;
        if exp.time != rec.time || want != kernel.outputs() {
            return Err(format!(
                "first mismatch at time {} (event {event:?}): expected {want:?}, model {:?}",
                rec.time,
                kernel.outputs()
            ));
        }
        compared += 1;
    }
    Ok(compared)
}

#[test]
fn written_vectors_replay_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_tooltouch"))
        .args([
            "control",
            "--controller",
            "fuzzy",
            "--force",
            "estimated",
            "--out",
        ])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let stdout = String::from_utf8_lossy(&status.stdout);
    assert!(
        stdout.contains("fuzzy") && stdout.contains("estimated"),
        "{stdout}"
    );
    let events = std::fs::read(dir.path().join("fuzzy_estimated.events.ttv")).unwrap();
    let outputs = std::fs::read(dir.path().join("fuzzy_estimated.outputs.ttv")).unwrap();
    assert!(dir.path().join("fuzzy_estimated.svg").exists());
    let n = replay(&events, &outputs).unwrap();
    // 13 s at 20 Hz plus the three commands
    assert_eq!(n, 260 + 3);

    // a flipped override byte in the expected outputs is found and reported with its time
    let mut bad = outputs.clone();
    let first_tick_override = 28 + 10; // header, first record's header, then override
    bad[first_tick_override] ^= 1;
    let err = replay(&events, &bad).unwrap_err();
    assert!(err.contains("first mismatch at time"), "{err}");

    // truncated and foreign files are errors, not panics
    let (_, mut it) = Records::new(&events[..events.len() - 5]).unwrap();
    assert!(it.any(|r| matches!(r, Err(WireError::Truncated { .. }))));
    assert!(matches!(
        Records::new(&events[..10]),
        Err(WireError::Truncated { .. })
    ));
    let mut foreign = events.clone();
    foreign[0] = b'Z';
    assert!(matches!(
        Records::new(&foreign),
        Err(WireError::BadMagic(_))
    ));
}
