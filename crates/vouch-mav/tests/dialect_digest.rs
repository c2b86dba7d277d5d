//! The default dialect is embedded as a build-time digest of ardupilotmega.xml (no XML DOM at
//! start-up). These tests tie the digest to the XML it came from: the dialect rebuilt from the
//! digest must equal the one read from the same XML files at run time, field by field.

use std::path::Path;

use vouch_testkit::Need;

use vouch_mav::dialect::raw::{read_digest, read_xml, write_digest};
use vouch_mav::dialect::{Dialect, DialectError, embedded_origin, load_dialect_file};

fn embedded() -> Option<Dialect> {
    match Dialect::default_dialect() {
        Ok(d) => Some(d),
        Err(DialectError::NoEmbedded) => {
            vouch_testkit::missing(Need::Shared, "the default dialect (build without it)")
        }
        Err(e) => panic!("{e}"),
    }
}

/// The XML folder build.rs digested, if it is still on this machine.
fn origin_xml() -> Option<std::path::PathBuf> {
    let p = Path::new(embedded_origin()).join("ardupilotmega.xml");
    if p.is_file() {
        Some(p)
    } else {
        vouch_testkit::missing(Need::Shared, &format!("{} (the digested XML)", p.display()))
    }
}

#[test]
fn digest_rebuilds_the_same_dialect_as_the_xml() {
    let (Some(d), Some(xml)) = (embedded(), origin_xml()) else { return };
    let x = load_dialect_file(&xml).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(d.name, x.name);
    assert_eq!(d.messages().len(), x.messages().len());
    for (a, b) in d.messages().iter().zip(x.messages()) {
        assert_eq!(
            (a.id, &a.name, a.crc_extra, a.base_len, a.max_len),
            (b.id, &b.name, b.crc_extra, b.base_len, b.max_len)
        );
        assert_eq!(a.fields.len(), b.fields.len(), "{}", a.name);
        for (f, g) in a.fields.iter().zip(&b.fields) {
            assert_eq!(
                (&f.name, f.ty, f.array_len, f.offset, f.is_extension, &f.enum_name),
                (&g.name, g.ty, g.array_len, g.offset, g.is_extension, &g.enum_name),
                "{}",
                a.name
            );
        }
        for f in &a.fields {
            assert!(a.field(&f.name).is_some(), "{}.{}", a.name, f.name);
        }
    }
    assert_eq!(d.enums().len(), x.enums().len());
    for (a, b) in d.enums().iter().zip(x.enums()) {
        assert_eq!((&a.name, a.bitmask, &a.entries), (&b.name, b.bitmask, &b.entries));
    }
    // lookups built from the digest work like those built from XML
    assert_eq!(d.enum_entry("MAV_CMD_DO_PARACHUTE"), x.enum_entry("MAV_CMD_DO_PARACHUTE"));
    assert!(d.enum_entry("MAV_CMD_DO_PARACHUTE").is_some());
}

#[test]
fn well_known_crc_extras_come_through_the_digest() {
    let Some(d) = embedded() else { return };
    // CRC_EXTRA values as published in PROTOCOL_FACTS.md / the MAVLink generator tables.
    for (name, extra) in [
        ("HEARTBEAT", 50u8),
        ("MISSION_COUNT", 221),
        ("MISSION_ITEM_INT", 38),
        ("COMMAND_LONG", 152),
        ("MISSION_ACK", 153),
    ] {
        assert_eq!(d.by_name(name).map(|m| m.crc_extra), Some(extra), "{name}");
    }
}

#[test]
fn digest_round_trips_and_rejects_broken_lines() {
    let files = [(
        "t.xml",
        "<mavlink><enums><enum name=\"E\" bitmask=\"true\"><entry name=\"A\" value=\"0x4\"/><entry name=\"B\"/></enum></enums>\
         <messages><message id=\"7\" name=\"X\"><field type=\"uint8_t[3]\" name=\"a\" enum=\"E\">a</field><extensions/><field type=\"float\" name=\"b\">b</field></message></messages></mavlink>",
    )];
    let read = |n: &str| -> Result<String, ()> {
        files.iter().find(|f| f.0 == n).map(|f| f.1.to_string()).ok_or(())
    };
    let raw = read_xml("t.xml", &read).unwrap_or_else(|_| panic!("read"));
    assert_eq!(raw.enums[0].entries, vec![("A".to_string(), 4), ("B".to_string(), 5)]);
    let text = write_digest(&raw).expect("digestible");
    assert_eq!(read_digest(&text).expect("readable"), raw);
    assert_eq!(read_digest("M 1 X f.xml\nF a uint8_t 0\n"), Err(2));
    assert_eq!(read_digest("V A 1\n"), Err(1));
    assert_eq!(read_digest("M notanumber X f.xml\n"), Err(1));
}
