//! docs/CONTRACT.md's SPI register map is the generator's (`spi_map_markdown` at the default
//! configuration): a register added to the map, or a changed range, fails here until the
//! table is updated.

use tooltouch_hdl_gen::spi::spi_map_markdown;
use tooltouch_model::MeasureConfig;

#[test]
fn the_contracts_spi_map_is_the_generated_one() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/CONTRACT.md");
    let doc = std::fs::read_to_string(path).expect("docs/CONTRACT.md");
    let table = spi_map_markdown(&MeasureConfig::default());
    assert!(
        doc.contains(&table),
        "docs/CONTRACT.md's SPI register map differs from the generator's; it is:\n{table}"
    );
}
