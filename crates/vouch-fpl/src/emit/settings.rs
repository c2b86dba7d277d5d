//! The settings upstream's build makes from a flight plan: every `<variable>` of the *main*
//! file's `<variables>` that has `min`, `max` and `step` becomes a `dl_setting` of the
//! "System" / "Flight Plan" group (procedures' variables never do), written as Paparazzi's
//! `settings.xml` and `settings.h` for an aircraft whose only configuration is the plan (a
//! full airframe adds telemetry and module settings first).
//!
//! Upstream details kept: the settings are in reverse order (the last variable gets index 0),
//! attributes as the reader left them (DTD order), short names from `var` (its `_`/`.`
//! separated parts cut to 3 characters, 16 characters at most), `handler` with `module` or
//! `header`, `persistent` settings of a fixed type list. Upstream's failures on a setting are
//! errors here: an empty short name (`var` empty or only `_`/`.`), `handler` with neither or
//! both of `module`/`header`, a persistent setting of unknown `type`.

use crate::ast::expanded::Node;
use crate::ast::{FlightPlan, VariableDecl};
use crate::passes::CompileError;
use crate::span::Span;

/// Paparazzi's `settings.xml` and `settings.h` of a plan.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Settings {
    /// `settings.xml`.
    pub xml: String,
    /// `settings.h`.
    pub header: String,
    /// Number of settings.
    pub count: usize,
}

/// One `dl_setting`: its attributes and where its variable is.
struct Setting {
    attrs: Vec<(String, String)>,
    span: Span,
}

impl Setting {
    fn get(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)).map(|(_, v)| v.as_str())
    }
    fn var(&self) -> &str {
        self.get("var").unwrap_or_default()
    }
    fn error(&self, msg: String) -> CompileError {
        CompileError::settings(msg, self.span)
    }
}

/// The settings of `plan` (see the module comment).
pub fn settings(plan: &FlightPlan, version: &str) -> Result<Settings, CompileError> {
    let mut list: Vec<Setting> = plan
        .variables
        .iter()
        .filter_map(|v| match v {
            VariableDecl::Var(v) if v.span.file.0 == 0 => Some(v),
            _ => None,
        })
        .filter(|v| ["min", "max", "step"].iter().all(|a| v.attrs.get(a).is_some()))
        .map(|v| Setting {
            attrs: v.attrs.0.iter().map(|a| (a.name.clone(), a.value.clone())).collect(),
            span: v.span,
        })
        .collect();
    list.reverse();
    let xml = settings_xml(&list);
    let mut h = Header { out: String::new(), margin: 0 };
    h.out.push_str(&format!(
        "/* This file has been generated from  */\n/* Version {version} */\n/* Please DO NOT EDIT */\n\n"
    ));
    h.out.push_str("#ifndef SETTINGS_H\n#define SETTINGS_H\n\n");
    dl_settings(&mut h, &list)?;
    persistent(&mut h, &list)?;
    h.out.push_str("\n#endif // SETTINGS_H\n");
    Ok(Settings { xml, header: h.out, count: list.len() })
}

fn settings_xml(list: &[Setting]) -> String {
    let settings =
        list.iter().map(|s| Node::new("dl_setting", s.attrs.clone(), Vec::new())).collect();
    let name = |n: &str| vec![("name".to_string(), n.to_string())];
    let system = if list.is_empty() {
        Node::new("dl_settings", name("System"), Vec::new())
    } else {
        let fp = Node::new("dl_settings", name("Flight Plan"), settings);
        Node::new("dl_settings", name("System"), vec![fp])
    };
    let root =
        Node::new("settings", Vec::new(), vec![Node::new("dl_settings", Vec::new(), vec![system])]);
    let mut out = String::new();
    super::dump::print_node(&mut out, &root);
    out
}

struct Header {
    out: String,
    margin: usize,
}

impl Header {
    fn line(&mut self, text: &str) {
        self.out.push_str(&" ".repeat(self.margin));
        self.out.push_str(text);
        self.out.push('\n');
    }
}

/// Upstream's short name: the `_`/`.` separated parts of `var`, each cut to 3 characters,
/// joined with `_`, at most 16 characters.
fn short_name(s: &Setting) -> Result<String, CompileError> {
    let parts: Vec<&str> = s.var().split(['_', '.']).filter(|p| !p.is_empty()).collect();
    let joined: String =
        parts.iter().map(|p| format!("_{}", p.chars().take(3).collect::<String>())).collect();
    if joined.is_empty() {
        return Err(s.error(format!(
            "setting '{}': no short name can be made of it (upstream fails with Invalid_argument)",
            s.var()
        )));
    }
    Ok(joined.chars().skip(1).take(16).collect())
}

fn dl_settings(h: &mut Header, list: &[Setting]) -> Result<(), CompileError> {
    h.line("");
    if !list.is_empty() {
        h.line("#include \"generated/flight_plan.h\"");
    }
    h.line("#include \"generated/modules.h\"");
    h.line("");
    h.out.push_str("#define SETTINGS_NAMES { \\\n");
    for s in list {
        h.out.push_str(&format!(" {{ \"{}\" }}, \\\n", s.var()));
    }
    h.line("};");
    h.out.push_str("#define SETTINGS_NAMES_SHORT { \\\n");
    for s in list {
        h.out.push_str(&format!(" \"{}\" , \\\n", short_name(s)?));
    }
    h.line("};");
    h.out.push_str(&format!("#define NB_SETTING {}\n", list.len()));
    h.line("#define DlSetting(_idx, _value) { \\");
    h.margin += 2;
    h.line("switch (_idx) { \\");
    h.margin += 2;
    for (i, s) in list.iter().enumerate() {
        let line = set_case(i, s)?;
        h.line(&line);
    }
    h.line("default: break;\\");
    h.margin -= 2;
    h.line("}\\");
    h.margin -= 2;
    h.line("}");
    h.line("#define PeriodicSendDlValue(_trans, _dev) { \\");
    if !list.is_empty() {
        h.margin += 2;
        h.line("static uint8_t i;\\");
        h.line("float var;\\");
        h.line(&format!("if (i >= {}) i = 0;\\", list.len()));
        h.line("switch (i) { \\");
        h.margin += 2;
        for (i, s) in list.iter().enumerate() {
            h.line(&format!("case {i}: var = {}; break;\\", value_of(s)));
        }
        h.line("default: var = 0.; break;\\");
        h.margin -= 2;
        h.line("}\\");
        h.line("pprz_msg_send_DL_VALUE(_trans, _dev, AC_ID, &i, &var);\\");
        h.line("i++;\\");
        h.margin -= 2;
    }
    h.line("}");
    h.line("static inline float settings_get_value(uint8_t i) {");
    h.margin += 2;
    h.line("switch (i) {");
    h.margin += 2;
    for (i, s) in list.iter().enumerate() {
        h.line(&format!("case {i}: return {};", value_of(s)));
    }
    h.line("default: return 0.;");
    h.margin -= 2;
    h.line("}");
    h.margin -= 2;
    h.line("}");
    Ok(())
}

/// The value a setting reads back (`fun` settings have none).
fn value_of(s: &Setting) -> &str {
    if s.get("type") == Some("fun") { "0" } else { s.var() }
}

/// The `DlSetting` case of one setting: plain assignment, or the handler of its module/header.
fn set_case(i: usize, s: &Setting) -> Result<String, CompileError> {
    let v = s.var();
    let Some(handler) = s.get("handler") else {
        return Ok(format!("case {i}: {v} = _value; break;\\"));
    };
    let basename = |p: &str| p.rsplit('/').next().unwrap_or(p).to_string();
    let module =
        match (s.get("module").unwrap_or(""), s.get("header").unwrap_or("")) {
            ("", "") => return Err(s.error(format!(
                "setting '{v}': handler '{handler}' needs a 'header' (or legacy 'module') attribute"
            ))),
            ("", m) | (m, "") => basename(m),
            _ => {
                return Err(s.error(format!(
                    "setting '{v}': handler '{handler}' with both 'module' and 'header' attributes"
                )));
            }
        };
    Ok(if s.get("type") == Some("fun") {
        format!("case {i}: {module}_{handler}( _value ); break;\\")
    } else {
        format!("case {i}: {module}_{handler}( _value ); _value = {v}; break;\\")
    })
}

/// The C type of a persistent setting's `type`.
fn c_type(s: &Setting) -> Result<&'static str, CompileError> {
    Ok(match s.get("type").unwrap_or("float") {
        "bool" | "uint8" => "uint8_t",
        "int8" => "int8_t",
        "int16" => "int16_t",
        "int32" => "int32_t",
        "int64" => "int64_t",
        "uint16" => "uint16_t",
        "uint32" => "uint32_t",
        "uint64" => "uint64_t",
        "float" => "float",
        "double" => "double",
        other => {
            return Err(s.error(format!(
                "persistent setting '{}': unknown type '{other}' (bool, int8…int64, uint8…uint64, float, double)",
                s.var()
            )))
        }
    })
}

fn persistent(h: &mut Header, list: &[Setting]) -> Result<(), CompileError> {
    let pers: Vec<&Setting> = list.iter().filter(|s| s.get("persistent").is_some()).collect();
    h.line("");
    h.line("/* Persistent Settings */");
    h.line("struct PersistentSettings {");
    h.margin += 2;
    for (i, s) in pers.iter().enumerate() {
        let line = format!("{} s_{i}; /* {} */", c_type(s)?, s.var());
        h.line(&line);
    }
    h.margin -= 2;
    h.line("};");
    h.line("");
    h.line("extern struct PersistentSettings pers_settings;");
    h.line("");
    h.line("static inline void persistent_settings_store( void ) {");
    h.margin += 2;
    for (i, s) in pers.iter().enumerate() {
        h.line(&format!("pers_settings.s_{i} = {};", s.var()));
    }
    h.margin -= 2;
    h.line("}");
    h.line("");
    h.line("static inline void persistent_settings_load( void ) {");
    h.margin += 2;
    for (i, s) in pers.iter().enumerate() {
        let line = match (s.get("handler"), s.get("module")) {
            (Some(handler), Some(m)) => {
                format!("{}_{handler}( pers_settings.s_{i} );", m.rsplit('/').next().unwrap_or(m))
            }
            _ => format!("{} = pers_settings.s_{i};", s.var()),
        };
        h.line(&line);
    }
    h.margin -= 2;
    h.line("}");
    Ok(())
}
