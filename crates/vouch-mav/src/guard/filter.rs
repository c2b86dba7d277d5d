//! Per-endpoint message filters, as mavlink-router has them: allow or block by message id, source
//! system and source component, on the way in (before routing) and on the way out (after it).
//! An empty allow list allows everything; an empty block list blocks nothing.

/// One direction's filter.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Filter {
    /// Only these message ids pass (`Allow…MsgId…`).
    pub allow_msg: Vec<u32>,
    /// These message ids never pass (`Block…MsgId…`).
    pub block_msg: Vec<u32>,
    /// Only frames from these source components pass.
    pub allow_src_comp: Vec<u8>,
    /// Frames from these source components never pass.
    pub block_src_comp: Vec<u8>,
    /// Only frames from these source systems pass.
    pub allow_src_sys: Vec<u8>,
    /// Frames from these source systems never pass.
    pub block_src_sys: Vec<u8>,
}

fn allowed<T: PartialEq>(allow: &[T], block: &[T], v: T) -> bool {
    (allow.is_empty() || allow.contains(&v)) && !block.contains(&v)
}

impl Filter {
    /// Whether a frame with message id `msgid` from `sysid/compid` passes.
    #[inline]
    pub fn passes(&self, msgid: u32, sysid: u8, compid: u8) -> bool {
        self.is_empty()
            || (allowed(&self.allow_msg, &self.block_msg, msgid)
                && allowed(&self.allow_src_comp, &self.block_src_comp, compid)
                && allowed(&self.allow_src_sys, &self.block_src_sys, sysid))
    }

    /// No list set: everything passes.
    pub fn is_empty(&self) -> bool {
        self.allow_msg.is_empty()
            && self.block_msg.is_empty()
            && self.allow_src_comp.is_empty()
            && self.block_src_comp.is_empty()
            && self.allow_src_sys.is_empty()
            && self.block_src_sys.is_empty()
    }
}

/// Both directions of one endpoint.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Filters {
    /// Applied to frames received on the endpoint, before they are checked and routed.
    pub inbound: Filter,
    /// Applied to frames about to be sent on the endpoint, after routing.
    pub outbound: Filter,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn allow_and_block_lists_as_mavlink_router_reads_them() {
        let f = Filter::default();
        assert!(f.passes(0, 1, 1) && f.is_empty());
        let f = Filter { allow_msg: vec![0, 33], ..Filter::default() };
        assert!(f.passes(0, 1, 1) && f.passes(33, 9, 9) && !f.passes(30, 1, 1));
        let f = Filter { block_msg: vec![30], block_src_sys: vec![42], ..Filter::default() };
        assert!(f.passes(0, 1, 1) && !f.passes(30, 1, 1) && !f.passes(0, 42, 1));
        // allow on one identifier, block on another
        let f = Filter { allow_src_sys: vec![1], block_msg: vec![0], ..Filter::default() };
        assert!(f.passes(33, 1, 1) && !f.passes(0, 1, 1) && !f.passes(33, 2, 1));
        let f = Filter { allow_src_comp: vec![1], ..Filter::default() };
        assert!(f.passes(0, 7, 1) && !f.passes(0, 7, 191));
    }
}
