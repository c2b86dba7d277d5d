//! Routing as mavlink-router does it. Every connection of an endpoint is a *route* that learns
//! the (system, component) ids of the frames it delivers. A frame received on one route is
//! offered to every other route, which
//!
//! 1. refuses it when it has seen the frame's sender itself (no loops; the route it came from
//!    always refuses),
//! 2. refuses it when the endpoint's outgoing filter does,
//! 3. takes it when it has no target system (no target fields, or target system 0), when it has
//!    seen the target system and component, or — target component 0 — the target system,
//! 4. takes everything when it has seen the sniffer system id,
//! 5. refuses it otherwise (a target that was never seen anywhere reaches no one).
//!
//! Endpoints in one group share what their routes have seen (parallel links to one system).
//! Target fields come from the dialect; without one every frame counts as having no target.
//! Memory is bounded: at most [`MAX_ROUTES`] routes, [`MAX_IDS_PER_ROUTE`] ids per route.

use std::sync::Arc;

use super::filter::Filter;
use super::link::Peer;
use crate::codec::FrameRef;
use crate::dialect::Dialect;
use crate::side::Side;

/// Most routes (connections of all endpoints) at once; the set of destinations of a frame is a
/// bit mask of this width.
pub const MAX_ROUTES: usize = 128;
/// Most (system, component) ids a route (or a group) remembers; later ones are not learned.
pub const MAX_IDS_PER_ROUTE: usize = 64;

/// A set of routes, by index.
pub type RouteMask = u128;

/// Where the target fields of each message are (byte offsets in the untruncated payload).
pub struct Targets {
    dialect: Arc<Dialect>,
    /// By message index: (target_system, target_component) offsets.
    offsets: Vec<(Option<u16>, Option<u16>)>,
}

impl Targets {
    /// The target offsets of every message of `dialect`.
    pub fn new(dialect: Arc<Dialect>) -> Targets {
        let offsets = dialect
            .messages()
            .iter()
            .map(|m| {
                let off = |name: &str| m.field(name).map(|f| f.offset);
                (off("target_system"), off("target_component"))
            })
            .collect();
        Targets { dialect, offsets }
    }

    /// (target system, target component) of a frame, `None` where the message has no such field
    /// or is unknown. A field cut by zero truncation reads as 0.
    pub fn of(&self, f: &FrameRef<'_>) -> (Option<u8>, Option<u8>) {
        let Some(i) = self.dialect.index_of_id(f.msgid()) else { return (None, None) };
        let p = f.payload();
        let read = |off: Option<u16>| off.map(|o| p.get(usize::from(o)).copied().unwrap_or(0));
        let (s, c) = self.offsets[usize::from(i)];
        (read(s), read(c))
    }
}

/// What the router knows of one frame when routing it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameInfo {
    pub msgid: u32,
    pub sysid: u8,
    pub compid: u8,
    pub target_sys: Option<u8>,
    pub target_comp: Option<u8>,
}

impl FrameInfo {
    /// The header fields of `f` and its targets (none without a target table).
    pub fn of(f: &FrameRef<'_>, targets: Option<&Targets>) -> FrameInfo {
        let (target_sys, target_comp) = targets.map_or((None, None), |t| t.of(f));
        FrameInfo {
            msgid: f.msgid(),
            sysid: f.sysid(),
            compid: f.compid(),
            target_sys,
            target_comp,
        }
    }
}

/// Ids seen by a route or a group: `sysid << 8 | compid`.
#[derive(Default, Debug)]
struct Known {
    ids: Vec<u16>,
}

impl Known {
    fn has(&self, sys: u8, comp: u8) -> bool {
        self.ids.contains(&(u16::from(sys) << 8 | u16::from(comp)))
    }
    fn has_sys(&self, sys: u8) -> bool {
        self.ids.iter().any(|&id| (id >> 8) as u8 == sys)
    }
}

/// One connection of one endpoint.
#[derive(Debug)]
pub struct Route {
    /// Index of its endpoint.
    pub endpoint: usize,
    /// Which connection.
    pub peer: Peer,
    /// Its endpoint's side.
    pub side: Side,
    /// Index into `Routes::known` (shared within a group).
    known: usize,
    /// `false` once closed (the slot is reused later; indices stay stable meanwhile).
    pub alive: bool,
}

/// Per endpoint: side, outgoing filter, and the known-ids slot of its group if it has one.
struct EndpointRouting {
    side: Side,
    outbound: Filter,
    group_slot: Option<usize>,
}

/// The routing table.
pub struct Routes {
    routes: Vec<Route>,
    known: Vec<Known>,
    endpoints: Vec<EndpointRouting>,
    sniffer: Option<u8>,
    /// Ids not learned because a table was full.
    pub ids_not_learned: u64,
}

/// How one route answered for one frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Accept {
    Yes,
    No,
    Filtered,
}

impl Routes {
    /// A table for endpoints given as (side, outgoing filter, group name).
    pub fn new(endpoints: &[(Side, Filter, Option<String>)], sniffer: Option<u8>) -> Routes {
        let mut known = Vec::new();
        let mut groups: Vec<(&str, usize)> = Vec::new();
        let endpoints = endpoints
            .iter()
            .map(|(side, outbound, group)| {
                let group_slot = group.as_deref().map(|g| {
                    groups.iter().find(|(n, _)| *n == g).map(|(_, s)| *s).unwrap_or_else(|| {
                        known.push(Known::default());
                        groups.push((g, known.len() - 1));
                        known.len() - 1
                    })
                });
                EndpointRouting { side: *side, outbound: outbound.clone(), group_slot }
            })
            .collect();
        Routes { routes: Vec::new(), known, endpoints, sniffer, ids_not_learned: 0 }
    }

    /// The route of connection `peer` of endpoint `ep`, opened if needed; `None` when the table
    /// is full.
    pub fn open(&mut self, ep: usize, peer: Peer) -> Option<usize> {
        if let Some(i) = self.find(ep, peer) {
            return Some(i);
        }
        let reuse = self.routes.iter().position(|r| !r.alive);
        if reuse.is_none() && self.routes.len() >= MAX_ROUTES {
            return None;
        }
        let known = match self.endpoints[ep].group_slot {
            Some(s) => s,
            None => self.free_slot(),
        };
        let route = Route { endpoint: ep, peer, side: self.endpoints[ep].side, known, alive: true };
        Some(match reuse {
            Some(i) => {
                self.routes[i] = route;
                i
            }
            None => {
                self.routes.push(route);
                self.routes.len() - 1
            }
        })
    }

    /// An empty known-ids slot: one that no live route and no group uses, or a new one.
    fn free_slot(&mut self) -> usize {
        let used = |s: usize| {
            self.routes.iter().any(|r| r.alive && r.known == s)
                || self.endpoints.iter().any(|e| e.group_slot == Some(s))
        };
        match (0..self.known.len()).find(|&s| !used(s)) {
            Some(s) => {
                self.known[s].ids.clear();
                s
            }
            None => {
                self.known.push(Known::default());
                self.known.len() - 1
            }
        }
    }

    /// The route of connection `peer` of endpoint `ep`, if open.
    pub fn find(&self, ep: usize, peer: Peer) -> Option<usize> {
        self.routes.iter().position(|r| r.alive && r.endpoint == ep && r.peer == peer)
    }

    /// Closes the route of a connection that went away.
    pub fn close(&mut self, ep: usize, peer: Peer) {
        if let Some(i) = self.find(ep, peer) {
            self.routes[i].alive = false;
        }
    }

    /// The route at index `i`.
    pub fn get(&self, i: usize) -> &Route {
        &self.routes[i]
    }

    /// Remembers that route `i` delivered a frame from `sys/comp`.
    pub fn learn(&mut self, i: usize, sys: u8, comp: u8) {
        let k = &mut self.known[self.routes[i].known];
        if !k.has(sys, comp) {
            if k.ids.len() < MAX_IDS_PER_ROUTE {
                k.ids.push(u16::from(sys) << 8 | u16::from(comp));
            } else {
                self.ids_not_learned += 1;
            }
        }
    }

    fn accepts(&self, r: &Route, f: &FrameInfo) -> Accept {
        let known = &self.known[r.known];
        if known.has(f.sysid, f.compid) {
            return Accept::No;
        }
        if !self.endpoints[r.endpoint].outbound.passes(f.msgid, f.sysid, f.compid) {
            return Accept::Filtered;
        }
        let reachable = match (f.target_sys, f.target_comp) {
            (None | Some(0), _) => true,
            (Some(s), Some(c)) if c > 0 => known.has(s, c),
            (Some(s), _) => known.has_sys(s),
        };
        if reachable || self.sniffer.is_some_and(|s| known.has_sys(s)) {
            Accept::Yes
        } else {
            Accept::No
        }
    }

    /// The routes a frame received on route `from` goes to, and the routes whose outgoing
    /// filter kept it.
    pub fn route(&self, from: usize, f: &FrameInfo) -> (RouteMask, RouteMask) {
        let mut mask = 0;
        let mut filtered = 0;
        for (i, r) in self.routes.iter().enumerate() {
            if i == from || !r.alive {
                continue;
            }
            match self.accepts(r, f) {
                Accept::Yes => mask |= 1 << i,
                Accept::Filtered => filtered |= 1 << i,
                Accept::No => {}
            }
        }
        (mask, filtered)
    }

    /// Every live route of side `side`.
    pub fn of_side(&self, side: Side) -> RouteMask {
        self.mask_where(|_, r| r.side == side)
    }

    /// Live routes of side `side` that have seen `sys/comp` (component 0: any component), or all
    /// of that side when none has.
    pub fn toward(&self, side: Side, sys: u8, comp: u8) -> RouteMask {
        let seen = self.mask_where(|_, r| {
            let k = &self.known[r.known];
            r.side == side && if comp == 0 { k.has_sys(sys) } else { k.has(sys, comp) }
        });
        if seen != 0 { seen } else { self.of_side(side) }
    }

    fn mask_where(&self, keep: impl Fn(usize, &Route) -> bool) -> RouteMask {
        self.routes
            .iter()
            .enumerate()
            .filter(|(i, r)| r.alive && keep(*i, r))
            .fold(0, |m, (i, _)| m | 1 << i)
    }
}

/// The indices in a mask, lowest first.
pub fn indices(mut mask: RouteMask) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let i = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            i
        })
    })
}

#[cfg(test)]
mod tests;
