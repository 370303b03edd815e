//! The vectors of a force-control run (`tooltouch control`'s `<stem>.events.ttv` and
//! `<stem>.outputs.ttv`): the input event stream and the model's outputs as binary streams.

use tooltouch_model::force::config::ForceConfig;
use tooltouch_model::force::events::ForceEvent;
use tooltouch_model::force::kernel::ForceOutputs;
use tooltouch_model::wire::force_chunks::force_config_chunks;
use tooltouch_model::wire::force_event::encode_force_event;
use tooltouch_model::wire::force_outputs::outputs_record;
use tooltouch_model::wire::{kind, Header, Record, StreamKind};

/// The event stream (the force configuration in `FORCE_CONFIG_CHUNK` records at time 0, then
/// every input event) and the output stream (the model's outputs after every non-sample
/// event) of a run, each ending with an END record; both headers carry `config`'s hash and
/// `tick_hz`.
pub fn streams(
    events: &[(u64, ForceEvent)],
    outputs: &[(u64, ForceOutputs)],
    config: &ForceConfig,
    tick_hz: u32,
) -> (Vec<u8>, Vec<u8>) {
    let force_hash = config.hash();
    let stream = |kind_: StreamKind, records: &mut dyn Iterator<Item = Record>| {
        let header = Header {
            stream: kind_,
            tick_hz,
            measure_hash: 0,
            force_hash,
        };
        let mut bytes = header.encode().to_vec();
        let mut buf = [0u8; 64];
        let mut last = 0;
        for rec in records {
            last = rec.time;
            let n = rec.encode(&mut buf).unwrap_or(0);
            bytes.extend_from_slice(&buf[..n]);
        }
        let n = Record::new(kind::END, last, &[])
            .encode(&mut buf)
            .unwrap_or(0);
        bytes.extend_from_slice(&buf[..n]);
        bytes
    };
    let events = stream(
        StreamKind::Events,
        &mut force_config_chunks(config, 0)
            .chain(events.iter().map(|(t, e)| encode_force_event(*t, e))),
    );
    let outputs = stream(
        StreamKind::Outputs,
        &mut outputs.iter().map(|(t, o)| outputs_record(*t, o)),
    );
    (events, outputs)
}
