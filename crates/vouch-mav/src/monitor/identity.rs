//! Who is who: the side of every frame and the systems shown to be vehicles — the trust
//! boundary of the tracked vehicle state.
//!
//! Live, the guard says on which side a frame arrived. A system is a *vehicle* once an autopilot
//! HEARTBEAT of it arrived on the vehicle side; from then on a frame on the GCS side that claims
//! one of the components that system has shown on the vehicle side (or component 0, which no
//! sender may use) is a forgery, and so is an autopilot HEARTBEAT on the GCS side. A component of
//! the vehicle's system that the vehicle side never showed — a companion computer (191) on a
//! ground endpoint of a router — is checked like any ground station and never believed about the
//! vehicle: vehicle state is learned only from vehicle-side frames of vehicles.
//!
//! Offline a recording has no sides, so they are derived from the heartbeats seen so far: a
//! system that sent an autopilot HEARTBEAT (MAV_TYPE not GCS, MAV_AUTOPILOT not INVALID) is on
//! the vehicle side with all its components; one whose heartbeats say MAV_TYPE_GCS is on the GCS
//! side; a system not classified yet falls back to the convention (system id ≥ 200 or component
//! 190 = ground station, anything else = vehicle side).

use crate::side::Side;
use crate::vehicle_state::HeartbeatKind;

/// What heartbeats have shown about one system id.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Shown {
    Nothing,
    Gcs,
    Vehicle,
}

/// Per system id: what it was shown to be (a fixed table, no allocation).
#[derive(Clone, Debug)]
pub(super) struct Identities {
    shown: [Shown; 256],
    /// Per system id, the component ids seen on the vehicle side (one bit each).
    vehicle_components: [[u64; 4]; 256],
}

/// Why a frame from the GCS side is refused as a forgery.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Forgery {
    /// Its ids are those of a vehicle's component that the vehicle side has shown (or component
    /// 0 of a vehicle).
    VehicleIds,
    /// It is a HEARTBEAT describing an autopilot.
    AutopilotHeartbeat,
}

impl Identities {
    pub(super) fn new() -> Self {
        Identities { shown: [Shown::Nothing; 256], vehicle_components: [[0; 4]; 256] }
    }

    fn component_shown(&self, sysid: u8, compid: u8) -> bool {
        let bits = &self.vehicle_components[usize::from(sysid)];
        bits[usize::from(compid >> 6)] & (1 << (compid & 63)) != 0
    }

    /// Whether `sysid` was shown to be a vehicle.
    #[inline]
    pub(super) fn is_vehicle(&self, sysid: u8) -> bool {
        self.shown[usize::from(sysid)] == Shown::Vehicle
    }

    /// Learns from a frame's heartbeat (if it is one) and returns the frame's side: `from` when
    /// the link says it, else the side derived from heartbeats (module documentation). A live
    /// frame is checked against the trust boundary: `Err` when it is a forgery (nothing is
    /// learned from it then).
    #[inline]
    pub(super) fn place(
        &mut self,
        sysid: u8,
        compid: u8,
        heartbeat: Option<HeartbeatKind>,
        from: Option<Side>,
    ) -> Result<Side, Forgery> {
        match from {
            Some(Side::Gcs) => {
                if self.is_vehicle(sysid) && (compid == 0 || self.component_shown(sysid, compid)) {
                    return Err(Forgery::VehicleIds);
                }
                let slot = &mut self.shown[usize::from(sysid)];
                match heartbeat {
                    Some(HeartbeatKind::Autopilot) => return Err(Forgery::AutopilotHeartbeat),
                    // a vehicle stays a vehicle whatever the ground side says
                    Some(HeartbeatKind::Gcs) if *slot != Shown::Vehicle => *slot = Shown::Gcs,
                    _ => {}
                }
                Ok(Side::Gcs)
            }
            Some(Side::Vehicle) => {
                self.vehicle_components[usize::from(sysid)][usize::from(compid >> 6)] |=
                    1 << (compid & 63);
                let slot = &mut self.shown[usize::from(sysid)];
                if heartbeat == Some(HeartbeatKind::Autopilot) {
                    *slot = Shown::Vehicle;
                }
                Ok(Side::Vehicle)
            }
            None => {
                let slot = &mut self.shown[usize::from(sysid)];
                match heartbeat {
                    Some(HeartbeatKind::Autopilot) => *slot = Shown::Vehicle,
                    Some(HeartbeatKind::Gcs) if *slot == Shown::Nothing => *slot = Shown::Gcs,
                    _ => {}
                }
                Ok(match *slot {
                    Shown::Vehicle => Side::Vehicle,
                    Shown::Gcs => Side::Gcs,
                    Shown::Nothing if sysid >= 200 || compid == 190 => Side::Gcs,
                    Shown::Nothing => Side::Vehicle,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use HeartbeatKind::*;

    #[test]
    fn offline_sides_follow_heartbeats_then_the_convention() {
        let mut ids = Identities::new();
        // before any heartbeat: the convention
        assert_eq!(ids.place(255, 0, None, None), Ok(Side::Gcs));
        assert_eq!(ids.place(9, 190, None, None), Ok(Side::Gcs));
        assert_eq!(ids.place(1, 1, None, None), Ok(Side::Vehicle));
        // a GCS heartbeat from a low system id, an autopilot heartbeat from a high one
        assert_eq!(ids.place(42, 7, Some(Gcs), None), Ok(Side::Gcs));
        assert_eq!(ids.place(42, 9, None, None), Ok(Side::Gcs));
        assert_eq!(ids.place(250, 1, Some(Autopilot), None), Ok(Side::Vehicle));
        assert_eq!(ids.place(250, 100, None, None), Ok(Side::Vehicle), "all its components");
        // a companion computer of the vehicle system stays on the vehicle side
        assert_eq!(ids.place(250, 194, Some(Other), None), Ok(Side::Vehicle));
        assert!(ids.is_vehicle(250) && !ids.is_vehicle(42));
    }

    #[test]
    fn live_frames_claiming_a_vehicle_identity_from_the_gcs_side_are_forgeries() {
        let mut ids = Identities::new();
        // before the vehicle spoke, its ids are nobody's: learned from nothing on the GCS side
        assert_eq!(ids.place(1, 1, None, Some(Side::Gcs)), Ok(Side::Gcs));
        assert_eq!(
            ids.place(1, 1, Some(Autopilot), Some(Side::Gcs)),
            Err(Forgery::AutopilotHeartbeat)
        );
        assert!(!ids.is_vehicle(1));
        assert_eq!(ids.place(1, 1, Some(Autopilot), Some(Side::Vehicle)), Ok(Side::Vehicle));
        assert!(ids.is_vehicle(1));
        // the vehicle side has shown components 1 and 154 (a gimbal) of system 1
        assert_eq!(ids.place(1, 154, None, Some(Side::Vehicle)), Ok(Side::Vehicle));
        for comp in [0, 1, 154] {
            assert_eq!(ids.place(1, comp, None, Some(Side::Gcs)), Err(Forgery::VehicleIds));
        }
        // a component it never showed (a companion computer on a ground endpoint) is a ground
        // sender like any other — but never with an autopilot heartbeat
        for comp in [190, 191, 250] {
            assert_eq!(ids.place(1, comp, None, Some(Side::Gcs)), Ok(Side::Gcs));
        }
        assert_eq!(
            ids.place(1, 191, Some(Autopilot), Some(Side::Gcs)),
            Err(Forgery::AutopilotHeartbeat)
        );
        assert_eq!(ids.place(1, 250, Some(Gcs), Some(Side::Gcs)), Ok(Side::Gcs));
        assert!(ids.is_vehicle(1), "a ground frame never changes what a vehicle was shown to be");
        assert_eq!(ids.place(1, 1, None, Some(Side::Gcs)), Err(Forgery::VehicleIds));
        assert_eq!(ids.place(255, 190, Some(Gcs), Some(Side::Gcs)), Ok(Side::Gcs));
        // a GCS heartbeat on the vehicle side does not make a system a GCS or a vehicle
        assert_eq!(ids.place(200, 1, Some(Gcs), Some(Side::Vehicle)), Ok(Side::Vehicle));
        assert!(!ids.is_vehicle(200));
    }
}
