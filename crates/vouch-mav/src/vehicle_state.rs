//! Vehicle state tracked from traffic, for refinements that depend on it (case studies II, III).
//!
//! Fed by HEARTBEAT (armed flag, custom mode), GLOBAL_POSITION_INT (relative altitude, vertical
//! speed), VFR_HUD (climb rate) and PARAM_VALUE / accepted PARAM_SET (parameter cache). Only the
//! parameters that loaded protocols mention are cached, so the update is a few byte compares.

use crate::codec::view::{read_chars, read_field};
use crate::codec::MessageView;
use crate::dialect::{Dialect, FieldDef, MsgIndex};

/// `MAV_MODE_FLAG_SAFETY_ARMED` bit of HEARTBEAT.base_mode.
const ARMED_FLAG: u64 = 128;
/// MAV_TYPE_GCS: heartbeats of ground stations say nothing about a vehicle.
const MAV_TYPE_GCS: u64 = 6;

/// State of one vehicle (one system id). `None` = not seen yet.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct VehicleState {
    pub armed: Option<bool>,
    pub custom_mode: Option<u32>,
    pub mav_type: Option<u8>,
    /// Altitude above home, metres (GLOBAL_POSITION_INT.relative_alt).
    pub alt_m: Option<f64>,
    /// Climb rate, metres per second, positive up (VFR_HUD.climb or −GLOBAL_POSITION_INT.vz).
    pub climb_ms: Option<f64>,
    /// Values of the tracked parameters, indexed like [`ParamTable::names`].
    pub params: Vec<Option<f64>>,
}

/// Precomputed field positions of the messages the tracker reads.
#[derive(Debug, Clone)]
struct Fields {
    heartbeat: Option<(MsgIndex, FieldDef, FieldDef, FieldDef, FieldDef)>,
    gpi: Option<(MsgIndex, FieldDef, FieldDef)>,
    vfr: Option<(MsgIndex, FieldDef)>,
    param_value: Option<(MsgIndex, FieldDef, FieldDef)>,
    param_set: Option<(MsgIndex, FieldDef, FieldDef, FieldDef)>,
}

/// Names of the parameters protocols refer to, interned at load time.
#[derive(Debug, Clone, Default)]
pub struct ParamTable {
    pub names: Vec<String>,
}

impl ParamTable {
    pub fn intern(&mut self, name: &str) -> usize {
        if let Some(i) = self.names.iter().position(|n| n == name) {
            return i;
        }
        self.names.push(name.to_string());
        self.names.len() - 1
    }

    fn find(&self, id: &[u8]) -> Option<usize> {
        self.names.iter().position(|n| n.as_bytes() == id)
    }
}

/// All vehicles' states, keyed by system id.
#[derive(Debug, Clone)]
pub struct VehicleTracker {
    fields: Fields,
    pub params: ParamTable,
    states: Vec<(u8, VehicleState)>,
}

fn field_of(d: &Dialect, msg: &str, f: &str) -> Option<FieldDef> {
    d.by_name(msg)?.field(f).cloned()
}

impl VehicleTracker {
    pub fn new(dialect: &Dialect, params: ParamTable) -> Self {
        let idx = |m: &str| dialect.index_of_name(m);
        let fields = Fields {
            heartbeat: (|| {
                Some((
                    idx("HEARTBEAT")?,
                    field_of(dialect, "HEARTBEAT", "base_mode")?,
                    field_of(dialect, "HEARTBEAT", "custom_mode")?,
                    field_of(dialect, "HEARTBEAT", "type")?,
                    field_of(dialect, "HEARTBEAT", "autopilot")?,
                ))
            })(),
            gpi: (|| {
                Some((
                    idx("GLOBAL_POSITION_INT")?,
                    field_of(dialect, "GLOBAL_POSITION_INT", "relative_alt")?,
                    field_of(dialect, "GLOBAL_POSITION_INT", "vz")?,
                ))
            })(),
            vfr: (|| Some((idx("VFR_HUD")?, field_of(dialect, "VFR_HUD", "climb")?)))(),
            param_value: (|| {
                Some((
                    idx("PARAM_VALUE")?,
                    field_of(dialect, "PARAM_VALUE", "param_id")?,
                    field_of(dialect, "PARAM_VALUE", "param_value")?,
                ))
            })(),
            param_set: (|| {
                Some((
                    idx("PARAM_SET")?,
                    field_of(dialect, "PARAM_SET", "param_id")?,
                    field_of(dialect, "PARAM_SET", "param_value")?,
                    field_of(dialect, "PARAM_SET", "target_system")?,
                ))
            })(),
        };
        VehicleTracker { fields, params, states: Vec::new() }
    }

    pub fn state(&self, sysid: u8) -> Option<&VehicleState> {
        self.states.iter().find(|(s, _)| *s == sysid).map(|(_, st)| st)
    }

    pub fn states(&self) -> impl Iterator<Item = (u8, &VehicleState)> {
        self.states.iter().map(|(s, st)| (*s, st))
    }

    fn state_mut(&mut self, sysid: u8) -> &mut VehicleState {
        if let Some(i) = self.states.iter().position(|(s, _)| *s == sysid) {
            return &mut self.states[i].1;
        }
        let n = self.params.names.len();
        self.states.push((sysid, VehicleState { params: vec![None; n], ..Default::default() }));
        let last = self.states.len() - 1;
        &mut self.states[last].1
    }

    /// Whether a heartbeat says its sender is a ground station. `None` if `msg` is no heartbeat.
    pub fn heartbeat_is_gcs(&self, msg: &MessageView) -> Option<bool> {
        let (idx, _, _, ty, _) = self.fields.heartbeat.as_ref()?;
        (msg.index == *idx).then(|| read_field(msg.payload, ty, 0).as_f64() as u64 == MAV_TYPE_GCS)
    }

    /// Updates state from a message sent by `sysid`. PARAM_SET is applied separately, once accepted.
    pub fn observe(&mut self, sysid: u8, compid: u8, msg: &MessageView) {
        let f = &self.fields;
        if let Some((idx, base_mode, custom_mode, ty, autopilot)) = &f.heartbeat {
            if msg.index == *idx {
                let t = read_field(msg.payload, ty, 0).as_f64() as u64;
                let ap = read_field(msg.payload, autopilot, 0).as_f64() as u64;
                // Only the autopilot's own heartbeat (component 1, or any non-GCS non-INVALID
                // autopilot) describes the vehicle; cameras, gimbals and GCSs do not.
                if t == MAV_TYPE_GCS || ap == 8 || (compid != 1 && ap == 0) {
                    return;
                }
                let armed = read_field(msg.payload, base_mode, 0).as_f64() as u64 & ARMED_FLAG != 0;
                let mode = read_field(msg.payload, custom_mode, 0).as_f64() as u32;
                let st = self.state_mut(sysid);
                st.armed = Some(armed);
                st.custom_mode = Some(mode);
                st.mav_type = Some(t as u8);
                return;
            }
        }
        if let Some((idx, rel_alt, vz)) = &f.gpi {
            if msg.index == *idx {
                let alt = read_field(msg.payload, rel_alt, 0).as_f64() / 1000.0;
                let climb = -read_field(msg.payload, vz, 0).as_f64() / 100.0;
                let st = self.state_mut(sysid);
                st.alt_m = Some(alt);
                st.climb_ms = Some(climb);
                return;
            }
        }
        if let Some((idx, climb)) = &f.vfr {
            if msg.index == *idx {
                let c = read_field(msg.payload, climb, 0).as_f64();
                self.state_mut(sysid).climb_ms = Some(c);
                return;
            }
        }
        if let Some((idx, id, value)) = &f.param_value {
            if msg.index == *idx && !self.params.names.is_empty() {
                if let Some(slot) = self.params.find(read_chars(msg.payload, id)) {
                    let v = read_field(msg.payload, value, 0).as_f64();
                    self.state_mut(sysid).params[slot] = Some(v);
                }
            }
        }
    }

    /// Applies an accepted PARAM_SET to the cache of its target vehicle.
    pub fn apply_param_set(&mut self, msg: &MessageView) {
        let Some((idx, id, value, target)) = &self.fields.param_set else {
            return;
        };
        if msg.index != *idx || self.params.names.is_empty() {
            return;
        }
        if let Some(slot) = self.params.find(read_chars(msg.payload, id)) {
            let v = read_field(msg.payload, value, 0).as_f64();
            let sys = read_field(msg.payload, target, 0).as_f64() as u8;
            self.state_mut(sys).params[slot] = Some(v);
        }
    }
}
