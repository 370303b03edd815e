//! `loadrt tooltouch` refuses a configuration that does not decode and one whose hash is
//! not the HAL file's, with a message naming both.

use crate::common::text;
use crate::hal::{halrun, work_dir, write_config};
use tooltouch_settings::firmware_config::FirmwareConfig;

#[test]
fn linuxcnc_a_bad_or_foreign_configuration_refuses_to_load() {
    let dir = work_dir();
    let settings = dir.path().join("settings.toml");
    std::fs::write(&settings, crate::bit_for_bit::SETTINGS).unwrap();
    let config_file = dir.path().join("config.ttc");
    write_config(&settings, &config_file);
    let hash = FirmwareConfig::load(Some(&settings))
        .unwrap()
        .measure
        .hash();
    let cut = dir.path().join("cut.ttc");
    std::fs::write(&cut, &std::fs::read(&config_file).unwrap()[..20]).unwrap();
    let cases = [
        (
            format!("{}", config_file.display()),
            "0123456789abcdef".to_string(),
            format!(
                "tooltouch: configuration mismatch: {} gives measure_hash {hash:016x}",
                config_file.display()
            ),
        ),
        (
            format!("{}", cut.display()),
            format!("{hash:016x}"),
            format!(
                "tooltouch: configuration {} does not decode: {}: the configuration file's measurement configuration says {} bytes, 10 are left (the HAL file names measure_hash={hash:016x})",
                cut.display(),
                cut.display(),
                tooltouch_model::wire::measure_config::CANONICAL_CONFIG_LEN
            ),
        ),
    ];
    for (file, named, want) in cases {
        let hal = format!(
            "loadrt threads name1=servo period1=1000000\nloadrt tooltouch config={file} measure_hash={named}\n"
        );
        let o = halrun(dir.path(), &hal);
        let log = text(&o);
        assert!(!o.status.success(), "{file} loaded:\n{log}");
        assert!(log.contains(&want), "expected `{want}` in:\n{log}");
        assert!(log.contains(&format!("measure_hash={named}")), "{log}");
    }
}
