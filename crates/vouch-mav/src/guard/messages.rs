//! The few messages the guard emits itself, framed as MAVLink 2 (values from common.xml:
//! STATUSTEXT id 253 CRC_EXTRA 83, MISSION_ACK 47/153, COMMAND_ACK 77/143).

use super::{Reply, Side};
use crate::codec::encode::{frame_v2_raw, zero_truncated_len};

pub const STATUSTEXT_ID: u32 = 253;
pub const STATUSTEXT_CRC_EXTRA: u8 = 83;
pub const MISSION_ACK_ID: u32 = 47;
pub const MISSION_ACK_CRC_EXTRA: u8 = 153;
pub const COMMAND_ACK_ID: u32 = 77;
pub const COMMAND_ACK_CRC_EXTRA: u8 = 143;
/// MAV_SEVERITY_WARNING.
pub const SEVERITY_WARNING: u8 = 4;

/// Frames `payload` (trailing zeros stripped, at least one byte kept) as MAVLink 2, unsigned, with
/// the codec's framer; the argument order is the guard's (source ids, then sequence number).
pub fn encode_v2(
    msgid: u32,
    crc_extra: u8,
    payload: &[u8],
    sysid: u8,
    compid: u8,
    seq: u8,
) -> Vec<u8> {
    let len = zero_truncated_len(payload);
    frame_v2_raw(msgid, crc_extra, &payload[..len], seq, sysid, compid)
}

/// STATUSTEXT{severity, text} toward the GCS; text is cut to the field's 50 bytes.
pub fn statustext(severity: u8, text: &str, sysid: u8, compid: u8) -> Reply {
    let mut payload = vec![0u8; 51];
    payload[0] = severity;
    let t = text.as_bytes();
    let n = t.len().min(50);
    payload[1..1 + n].copy_from_slice(&t[..n]);
    Reply {
        to: Side::Gcs,
        msgid: STATUSTEXT_ID,
        crc_extra: STATUSTEXT_CRC_EXTRA,
        payload,
        sysid,
        compid,
    }
}

/// MISSION_ACK{target, result, mission_type} as an answer from `(sysid, compid)`.
pub fn mission_ack(
    to: Side,
    sysid: u8,
    compid: u8,
    target: (u8, u8),
    result: u8,
    mission_type: u8,
) -> Reply {
    let payload = vec![target.0, target.1, result, mission_type];
    Reply { to, msgid: MISSION_ACK_ID, crc_extra: MISSION_ACK_CRC_EXTRA, payload, sysid, compid }
}

/// COMMAND_ACK{command, result} addressed to `target`.
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
    Reply { to, msgid: COMMAND_ACK_ID, crc_extra: COMMAND_ACK_CRC_EXTRA, payload, sysid, compid }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hex(v: &[u8]) -> String {
        v.iter().map(|b| format!("{b:02x}")).collect()
    }

    // Expected bytes produced by pymavlink 2.4.50 (MAVLINK20=1, source 1/191, seq 0):
    // statustext_encode(4, b"vouch: hi") and mission_ack_encode(255, 230, 13).
    #[test]
    fn matches_pymavlink_encoding() {
        let st = statustext(4, "vouch: hi", 1, 191);
        assert_eq!(
            hex(&encode_v2(st.msgid, st.crc_extra, &st.payload, 1, 191, 0)),
            "fd0a00000001bffd000004766f7563683a20686985e7"
        );
        let ack = mission_ack(Side::Gcs, 1, 191, (255, 230), 13, 0);
        assert_eq!(
            hex(&encode_v2(ack.msgid, ack.crc_extra, &ack.payload, 1, 191, 0)),
            "fd0300000001bf2f0000ffe60d2b3d"
        );
    }
}
