//! docs/CONTRACT.md is what an RTL team implements from: its port table must be the
//! generated `tt_frontend`'s ports (names, directions, widths at two configurations, the
//! reset value of every output), and `tt_config.vh` must carry the configuration.

use tooltouch_hdl_gen::{config_include, generate, Options, TOP};
use tooltouch_model::measure::config::{ChargeLaw, DecisionMethod};
use tooltouch_model::{FrontEnd, MeasureConfig, MeasureSettings};

/// The rows of the contract's port table: (port, direction, width formula, reset).
fn contract_ports() -> Vec<(String, String, String, String)> {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/CONTRACT.md"))
        .expect("docs/CONTRACT.md");
    let table = text
        .split("<!-- ports: begin -->")
        .nth(1)
        .and_then(|t| t.split("<!-- ports: end -->").next())
        .expect("the port table's markers");
    table
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| {
            let cells: Vec<String> = l
                .split('|')
                .map(|c| c.trim().trim_matches('`').to_string())
                .collect();
            (
                cells[1].clone(),
                cells[2].clone(),
                cells[3].clone(),
                cells[4].clone(),
            )
        })
        .collect()
}

/// The ports of the generated top: (name, direction, width), in declaration order.
fn generated_ports(config: &MeasureConfig) -> Vec<(String, String, u32)> {
    let design = generate(config, &Options::default());
    let top = design
        .files
        .iter()
        .find(|f| f.name == format!("{TOP}.v"))
        .expect("the top's file");
    let header = top
        .text
        .split(&format!("module {TOP} ("))
        .nth(1)
        .and_then(|t| t.split(");").next())
        .expect("the port list");
    header
        .lines()
        .filter_map(|l| {
            let code = l
                .split("//")
                .next()
                .unwrap_or("")
                .trim()
                .trim_end_matches(',');
            let words: Vec<&str> = code.split_whitespace().collect();
            let dir = *words.first()?;
            if dir != "input" && dir != "output" {
                return None;
            }
            let name = words.last()?.to_string();
            let width = words.iter().find(|w| w.starts_with('[')).map_or(1, |r| {
                let msb: u32 = r
                    .trim_matches(['[', ']'])
                    .split(':')
                    .next()
                    .unwrap()
                    .parse()
                    .unwrap();
                msb + 1
            });
            Some((name, dir.to_string(), width))
        })
        .collect()
}

fn width_of(formula: &str, config: &MeasureConfig) -> u32 {
    let s = config.settings();
    match formula {
        "scale_bits" => s.scale_bits.into(),
        "count_bits" => config.count_bits().into(),
        "charge_bits" => s.charge_bits.into(),
        n => n.parse().unwrap_or_else(|_| {
            panic!("width `{n}` in docs/CONTRACT.md is no formula this test knows")
        }),
    }
}

#[test]
fn contract_port_table_is_the_generated_tt_frontend() {
    let other = MeasureSettings {
        pulses_per_rev: 100,
        window_revs: 3,
        i_def: 7,
        charge_bits: 9,
        charge_law: ChargeLaw::Exponential {
            charge_shift: 2,
            discharge_shift: 3,
        },
        fire_threshold: 300,
        rearm_threshold: 20,
        scale_bits: 13,
        method: DecisionMethod::Density,
        ..MeasureSettings::default()
    }
    .validate()
    .unwrap();
    let rows = contract_ports();
    for config in [MeasureConfig::default(), other] {
        let ports = generated_ports(&config);
        let documented: Vec<(String, String, u32)> = rows
            .iter()
            .map(|(n, d, w, _)| (n.clone(), d.clone(), width_of(w, &config)))
            .collect();
        assert_eq!(
            documented, ports,
            "docs/CONTRACT.md's port table against {TOP}.v"
        );
        // Reset values: the model's power-on outputs.
        let reset = FrontEnd::new(&config).outputs();
        let values = tooltouch_hdl_gen::output_values(&config, &reset);
        let fields = tooltouch_hdl_gen::output_fields(&config);
        for (name, _, _, documented) in &rows {
            let want = match name.as_str() {
                "irq" => Some(u64::from(reset.register_now)),
                n => fields.iter().position(|f| f.name == n).map(|i| values[i]),
            };
            match want {
                Some(v) => assert_eq!(documented, &v.to_string(), "reset of `{name}`"),
                None if name == "mcu_rdata" => assert_eq!(documented, "the addressed word"),
                None => assert_eq!(documented, "—", "`{name}` is an input"),
            }
        }
    }
}

#[test]
fn contract_config_include_carries_the_configuration() {
    let config = MeasureConfig::default();
    let text = config_include(&config).text;
    let value = |name: &str| -> String {
        text.lines()
            .find(|l| l.split_whitespace().nth(2) == Some(name))
            .and_then(|l| l.split('=').nth(1))
            .and_then(|v| v.split(';').next())
            .map(|v| v.trim().to_string())
            .unwrap_or_else(|| panic!("no {name} in tt_config.vh:\n{text}"))
    };
    let s = config.settings();
    assert_eq!(value("I_DEF"), s.i_def.to_string());
    assert_eq!(value("COUNT_BITS"), config.count_bits().to_string());
    assert_eq!(value("WINDOW_PULSES"), config.window_pulses().to_string());
    assert_eq!(value("LATENCY_CYCLES"), config.latency_cycles().to_string());
    assert_eq!(value("FIRE_THRESHOLD"), s.fire_threshold.to_string());
    assert_eq!(value("CONFIG_HASH"), format!("64'h{:016x}", config.hash()));
    assert_eq!(
        value("FES_TIMEOUT_CYCLES"),
        s.checks.fes_timeout_cycles.to_string()
    );
    assert_eq!(value("CONFIRM_COUNT"), config.confirm_count().to_string());
    // count_bits = ceil(log2(ppr * window_revs + 1)), as the contract states.
    let w = f64::from(config.window_pulses());
    assert_eq!(
        u32::from(config.count_bits()),
        (w + 1.0).log2().ceil() as u32
    );
}
