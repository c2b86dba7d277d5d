//! Vehicle state tracked from traffic, for refinements that depend on it (case studies II, III).
//!
//! Fed by HEARTBEAT (armed flag, custom mode), GLOBAL_POSITION_INT (relative altitude, vertical
//! speed), VFR_HUD (climb rate) and PARAM_VALUE (parameter cache). Only the parameters that
//! loaded protocols mention are cached, so the update is a few byte compares. The tracker
//! believes what it is given: the monitor feeds it only frames from the vehicle side, from a
//! system that side has shown to be a vehicle (the trust boundary, see `monitor`).

use std::collections::HashMap;

use crate::codec::MessageView;
use crate::codec::view::{read_chars, read_field};
use crate::dialect::{Dialect, FieldDef, MsgIndex};

/// `MAV_MODE_FLAG_SAFETY_ARMED` bit of HEARTBEAT.base_mode.
const ARMED_FLAG: u64 = 128;
/// MAV_TYPE_GCS: heartbeats of ground stations say nothing about a vehicle.
const MAV_TYPE_GCS: u64 = 6;
/// MAV_AUTOPILOT_GENERIC.
const AUTOPILOT_GENERIC: u64 = 0;
/// MAV_AUTOPILOT_INVALID: the sender is no flight controller (GCS, camera, companion, …).
const AUTOPILOT_INVALID: u64 = 8;

/// What a HEARTBEAT says its sender is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeartbeatKind {
    /// MAV_TYPE_GCS.
    Gcs,
    /// A flight controller: not a GCS, autopilot not INVALID, and component 1 or a named
    /// autopilot (a GENERIC autopilot elsewhere than component 1 is some other device).
    Autopilot,
    /// Anything else (camera, gimbal, companion computer, …): it belongs to the side of its
    /// system.
    Other,
}

/// State of one vehicle (one system id). `None` = not seen yet.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct VehicleState {
    pub armed: Option<bool>,
    pub custom_mode: Option<u32>,
    pub mav_type: Option<u8>,
    /// Component id of the autopilot (the sender of its heartbeats): replies made in the
    /// vehicle's name come from it.
    pub autopilot_comp: Option<u8>,
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
}

/// Names of the parameters protocols refer to, interned at load time (with the whole family of
/// an interpolated id such as `"SERVO{n}_FUNCTION"`, so that outputs chosen by number at run
/// time are known).
#[derive(Debug, Clone, Default)]
pub struct ParamTable {
    pub names: Vec<String>,
    /// Upper-case id → slot, for the lookup of every PARAM_VALUE.
    index: HashMap<Vec<u8>, usize>,
}

/// Parameter ids have at most this many bytes (PARAM_VALUE.param_id).
const PARAM_ID_MAX: usize = 16;

impl ParamTable {
    pub fn intern(&mut self, name: &str) -> usize {
        let key = name.as_bytes().to_ascii_uppercase();
        if let Some(&i) = self.index.get(&key) {
            return i;
        }
        self.names.push(name.to_string());
        self.index.insert(key, self.names.len() - 1);
        self.names.len() - 1
    }

    /// The slot of a parameter id, matched without regard to ASCII case (as ArduPilot does).
    pub fn find(&self, id: &[u8]) -> Option<usize> {
        let mut key = [0u8; PARAM_ID_MAX];
        let upper = key.get_mut(..id.len())?;
        upper.copy_from_slice(id);
        upper.make_ascii_uppercase();
        self.index.get(&upper[..]).copied()
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
        };
        VehicleTracker { fields, params, states: Vec::new() }
    }

    pub fn state(&self, sysid: u8) -> Option<&VehicleState> {
        self.states.iter().find(|(s, _)| *s == sysid).map(|(_, st)| st)
    }

    /// The state of the vehicle a message addressed to system `sysid` reaches: that vehicle,
    /// or for a broadcast (system 0) the only vehicle known (`None` when there are several).
    pub fn addressed(&self, sysid: u8) -> Option<&VehicleState> {
        match (sysid, self.states.as_slice()) {
            (0, [(_, only)]) => Some(only),
            (0, _) => None,
            (s, _) => self.state(s),
        }
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

    /// What a heartbeat from component `compid` says its sender is; `None` if `msg` is no
    /// heartbeat.
    pub fn heartbeat_kind(&self, msg: &MessageView, compid: u8) -> Option<HeartbeatKind> {
        let (idx, _, _, ty, autopilot) = self.fields.heartbeat.as_ref()?;
        if msg.index != *idx {
            return None;
        }
        let t = read_field(msg.payload, ty, 0).as_f64() as u64;
        let ap = read_field(msg.payload, autopilot, 0).as_f64() as u64;
        Some(if t == MAV_TYPE_GCS {
            HeartbeatKind::Gcs
        } else if ap == AUTOPILOT_INVALID || (compid != 1 && ap == AUTOPILOT_GENERIC) {
            HeartbeatKind::Other
        } else {
            HeartbeatKind::Autopilot
        })
    }

    /// Updates state from a message sent by `sysid/compid` (a frame the monitor trusts).
    pub fn observe(&mut self, sysid: u8, compid: u8, msg: &MessageView) {
        let f = &self.fields;
        if let Some((idx, base_mode, custom_mode, ty, _)) = &f.heartbeat
            && msg.index == *idx
        {
            // Only the autopilot's own heartbeat describes the vehicle; cameras, gimbals and
            // GCSs do not.
            if self.heartbeat_kind(msg, compid) != Some(HeartbeatKind::Autopilot) {
                return;
            }
            let t = read_field(msg.payload, ty, 0).as_f64() as u64;
            let armed = read_field(msg.payload, base_mode, 0).as_f64() as u64 & ARMED_FLAG != 0;
            let mode = read_field(msg.payload, custom_mode, 0).as_f64() as u32;
            let st = self.state_mut(sysid);
            st.armed = Some(armed);
            st.custom_mode = Some(mode);
            st.mav_type = Some(t as u8);
            st.autopilot_comp = Some(compid);
            return;
        }
        if let Some((idx, rel_alt, vz)) = &f.gpi
            && msg.index == *idx
        {
            let alt = read_field(msg.payload, rel_alt, 0).as_f64() / 1000.0;
            let climb = -read_field(msg.payload, vz, 0).as_f64() / 100.0;
            let st = self.state_mut(sysid);
            st.alt_m = Some(alt);
            st.climb_ms = Some(climb);
            return;
        }
        if let Some((idx, climb)) = &f.vfr
            && msg.index == *idx
        {
            let c = read_field(msg.payload, climb, 0).as_f64();
            self.state_mut(sysid).climb_ms = Some(c);
            return;
        }
        if let Some((idx, id, value)) = &f.param_value
            && msg.index == *idx
            && !self.params.names.is_empty()
            && let Some(slot) = self.params.find(read_chars(msg.payload, id))
        {
            let v = read_field(msg.payload, value, 0).as_f64();
            self.state_mut(sysid).params[slot] = Some(v);
        }
    }
}
