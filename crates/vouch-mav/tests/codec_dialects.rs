//! Dialect loading: message and enum counts of ../shared/mavlink/definitions (as its README
//! lists them), includes, the embedded default, and located errors for broken XML.

use std::path::{Path, PathBuf};

use vouch_testkit::Need;

use vouch_mav::dialect::{Dialect, DialectError, load_dialect_file, load_dialect_from};

fn defs() -> Option<PathBuf> {
    vouch_testkit::shared("mavlink/definitions", "common.xml")
}

#[test]
fn message_counts_match_the_definitions_readme() {
    let Some(dir) = defs() else { return };
    let count = |f: &str| {
        load_dialect_file(&dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}")).messages().len()
    };
    assert_eq!(count("minimal.xml"), 1);
    assert_eq!(count("common.xml"), 234);
    assert_eq!(count("ardupilotmega.xml"), 325);
    assert_eq!(count("development.xml"), 248);
    assert_eq!(count("all.xml"), 391);
    let common = load_dialect_file(&dir.join("common.xml")).unwrap();
    assert_eq!(common.enums().len(), 160, "151 own enums + 9 from standard/minimal");
    // This copy is newer than pymavlink's: MISSION_COUNT has opaque_id.
    assert!(common.by_name("MISSION_COUNT").unwrap().field("opaque_id").is_some());
}

#[test]
fn every_message_of_all_xml_has_a_consistent_layout() {
    let Some(dir) = defs() else { return };
    let d = load_dialect_file(&dir.join("all.xml")).unwrap();
    for m in d.messages() {
        let mut end = 0u16;
        for f in &m.fields {
            assert_eq!(f.offset, end, "{}.{} offset", m.name, f.name);
            end += f.wire_size() as u16;
        }
        assert_eq!(end, m.max_len, "{}", m.name);
        assert!(m.base_len <= m.max_len);
        assert!(m.max_len <= 255);
        assert_eq!(d.by_id(m.id).map(|x| x.name.as_str()), Some(m.name.as_str()));
    }
}

#[test]
fn embedded_default_is_ardupilotmega_with_includes() {
    let d = match Dialect::default_dialect() {
        Ok(d) => d,
        Err(DialectError::NoEmbedded) => {
            return vouch_testkit::missing(Need::Shared, "the default dialect (build without it)")
                .unwrap_or(());
        }
        Err(e) => panic!("{e}"),
    };
    assert_eq!(d.name, "ardupilotmega");
    assert!(d.messages().len() >= 320, "{}", d.messages().len());
    for m in [
        "HEARTBEAT",
        "MISSION_ITEM_INT",
        "COMMAND_LONG",
        "PARAM_EXT_SET",
        "AHRS2",
        "UAVIONIX_ADSB_OUT_CFG",
    ] {
        assert!(d.by_name(m).is_some(), "{m}");
    }
    assert!(!vouch_mav::dialect::embedded_origin().is_empty());
}

#[test]
fn broken_dialects_are_reported_with_their_location() {
    let files = [
        ("root.xml", "<mavlink><include>missing.xml</include></mavlink>"),
        (
            "bad.xml",
            "<mavlink>\n<messages>\n<message id=\"1\" name=\"X\"><field type=\"uint8_t\" name=\"a\"></message>\n</messages></mavlink>",
        ),
        (
            "type.xml",
            "<mavlink><messages><message id=\"1\" name=\"X\"><field type=\"uint7_t\" name=\"a\">a</field></message></messages></mavlink>",
        ),
    ];
    let read = |name: &str| -> Result<String, DialectError> {
        files.iter().find(|(n, _)| *n == name).map(|(_, t)| t.to_string()).ok_or_else(|| {
            DialectError::Io {
                path: name.to_string(),
                source: std::io::Error::from(std::io::ErrorKind::NotFound),
            }
        })
    };
    let e = load_dialect_from("root.xml", &read).unwrap_err().to_string();
    assert!(e.contains("missing.xml"), "{e}");
    match load_dialect_from("bad.xml", &read).unwrap_err() {
        DialectError::Xml(e) => {
            assert_eq!((e.file.as_str(), e.line), ("bad.xml", 3), "{e}");
            // the label points into line 3 of the file's text
            let at = e.span.expect("located").offset();
            assert_eq!(files[1].1[..at].matches('\n').count(), 2, "{e}");
            let code = miette::Diagnostic::code(&*e).map(|c| c.to_string());
            assert_eq!(code.as_deref(), Some("mav::D002"));
        }
        other => panic!("expected an XML error, got {other}"),
    }
    let e = load_dialect_from("type.xml", &read).unwrap_err().to_string();
    assert!(e.contains("unknown type uint7_t"), "{e}");
    assert!(load_dialect_file(Path::new("/nonexistent/x.xml")).is_err());
}
