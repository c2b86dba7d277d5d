//! The few messages the guard makes itself, as [`Reply`]s framed without a dialect (values from
//! common.xml: STATUSTEXT id 253 CRC_EXTRA 83, MISSION_ACK 47/153, COMMAND_ACK 77/143).

use crate::monitor::Reply;
use crate::side::Side;

/// STATUSTEXT message id.
pub const STATUSTEXT_ID: u32 = 253;
/// STATUSTEXT CRC_EXTRA.
pub const STATUSTEXT_CRC_EXTRA: u8 = 83;
/// MISSION_ACK message id.
pub const MISSION_ACK_ID: u32 = 47;
/// MISSION_ACK CRC_EXTRA.
pub const MISSION_ACK_CRC_EXTRA: u8 = 153;
/// COMMAND_ACK message id.
pub const COMMAND_ACK_ID: u32 = 77;
/// COMMAND_ACK CRC_EXTRA.
pub const COMMAND_ACK_CRC_EXTRA: u8 = 143;
/// MAV_SEVERITY_WARNING.
pub const SEVERITY_WARNING: u8 = 4;

fn reply(
    message: &str,
    to: Side,
    (msgid, crc_extra): (u32, u8),
    payload: Vec<u8>,
    from: (u8, u8),
    target: (u8, u8),
    fields: Vec<(String, f64)>,
) -> Reply {
    Reply {
        message: message.to_string(),
        to,
        msgid,
        crc_extra,
        payload,
        fields,
        text_fields: Vec::new(),
        from_sys: from.0,
        from_comp: from.1,
        to_sys: target.0,
        to_comp: target.1,
    }
}

/// STATUSTEXT{severity, text} toward the GCS from `(sysid, compid)`; text is cut to the field's
/// 50 bytes.
pub fn statustext(severity: u8, text: &str, sysid: u8, compid: u8) -> Reply {
    let mut payload = vec![0u8; 51];
    payload[0] = severity;
    let t = text.as_bytes();
    let n = t.len().min(50);
    payload[1..1 + n].copy_from_slice(&t[..n]);
    let mut r = reply(
        "STATUSTEXT",
        Side::Gcs,
        (STATUSTEXT_ID, STATUSTEXT_CRC_EXTRA),
        payload,
        (sysid, compid),
        (0, 0),
        vec![("severity".into(), f64::from(severity))],
    );
    r.text_fields.push(("text".into(), String::from_utf8_lossy(&t[..n]).into_owned()));
    r
}

/// MISSION_ACK{target, result, mission_type} sent to `to` as an answer from `(sysid, compid)`.
pub fn mission_ack(
    to: Side,
    sysid: u8,
    compid: u8,
    target: (u8, u8),
    result: u8,
    mission_type: u8,
) -> Reply {
    let payload = vec![target.0, target.1, result, mission_type];
    let fields =
        vec![("type".into(), f64::from(result)), ("mission_type".into(), f64::from(mission_type))];
    let id = (MISSION_ACK_ID, MISSION_ACK_CRC_EXTRA);
    reply("MISSION_ACK", to, id, payload, (sysid, compid), target, fields)
}

/// COMMAND_ACK{command, result} sent to `to` (addressed to `target`) from `(sysid, compid)`.
pub fn command_ack(
    to: Side,
    sysid: u8,
    compid: u8,
    target: (u8, u8),
    command: u16,
    result: u8,
) -> Reply {
    let c = command.to_le_bytes();
    // wire order: command u16, result u8, progress u8, result_param2 i32, target_system, target_component
    let payload = vec![c[0], c[1], result, 0, 0, 0, 0, 0, target.0, target.1];
    let fields = vec![("command".into(), f64::from(command)), ("result".into(), f64::from(result))];
    let id = (COMMAND_ACK_ID, COMMAND_ACK_CRC_EXTRA);
    reply("COMMAND_ACK", to, id, payload, (sysid, compid), target, fields)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Expected bytes produced by pymavlink 2.4.50 (MAVLINK20=1, source 1/191, seq 0):
    // statustext_encode(4, b"vouch: hi") and mission_ack_encode(255, 230, 13).
    #[test]
    fn matches_pymavlink_encoding() {
        let st = statustext(4, "vouch: hi", 1, 191);
        assert_eq!(hex::encode(st.encode_v2(0)), "fd0a00000001bffd000004766f7563683a20686985e7");
        let ack = mission_ack(Side::Gcs, 1, 191, (255, 230), 13, 0);
        assert_eq!(hex::encode(ack.encode_v2(0)), "fd0300000001bf2f0000ffe60d2b3d");
    }
}
