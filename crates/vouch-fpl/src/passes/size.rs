//! Pass 2, *size verification*: FPE → FPS. The runtime stores block and stage numbers in
//! `uint8_t` (`nav_block`, `nav_stage`, `last_*`), so a plan may have at most 256 blocks and
//! each block at most 256 stages including its default stage. Upstream does not check this
//! (quirk 2: `Block(300)` is silently unreachable); vouch rejects such plans here.
//!
//! [`Fps`] holds numbers as [`BlockNo`]/[`StageNo`], `u8` newtypes whose constructors are
//! private to this module: the only way to obtain an FPS is [`verify`], so the generation pass
//! cannot be handed an ill-sized or ill-numbered plan.

use serde::Serialize;

use super::CompileError;
use super::extend::{Ext, ExtBlock, ExtException, ExtForbidden, ExtKind, ExtStage, Fpe};

/// The largest count representable by `uint8_t` numbers 0..=255.
pub const MAX_BLOCKS: usize = 256;
pub const MAX_STAGES: usize = 256;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct BlockNo(u8);

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct StageNo(u8);

impl BlockNo {
    pub fn get(self) -> u8 {
        self.0
    }
}

impl StageNo {
    pub fn get(self) -> u8 {
        self.0
    }
}

impl std::fmt::Display for BlockNo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl std::fmt::Display for StageNo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

/// A well-sized, well-numbered extended plan (the paper's FPS).
#[derive(Debug, Clone, Serialize)]
pub struct Fps(Ext<StageNo, BlockNo>);

impl Fps {
    pub fn plan(&self) -> &Ext<StageNo, BlockNo> {
        &self.0
    }
    /// `NB_BLOCK`: number of blocks including `HOME` (1..=256).
    pub fn nb_block(&self) -> usize {
        self.0.blocks.len()
    }
}

fn block_no(i: usize, n_blocks: usize) -> Result<BlockNo, CompileError> {
    if i >= n_blocks {
        return Err(CompileError::size(
            format!("reference to block {i}, but the plan has {n_blocks} blocks"),
            None,
        ));
    }
    u8::try_from(i)
        .map(BlockNo)
        .map_err(|_| CompileError::size(format!("block number {i} does not fit in uint8_t"), None))
}

/// A stage kind with its block references checked and typed.
fn checked_kind(kind: ExtKind<usize>, n: usize) -> Result<ExtKind<BlockNo>, CompileError> {
    Ok(match kind {
        ExtKind::Deroute { target } => ExtKind::Deroute { target: block_no(target, n)? },
        ExtKind::WhileTest { cond, label, end_label } => {
            ExtKind::WhileTest { cond, label, end_label }
        }
        ExtKind::EndWhile { label, end_label } => ExtKind::EndWhile { label, end_label },
        ExtKind::ForInit { var, from, to } => ExtKind::ForInit { var, from, to },
        ExtKind::ForTest { var, label, end_label } => ExtKind::ForTest { var, label, end_label },
        ExtKind::EndFor { label, end_label } => ExtKind::EndFor { label, end_label },
        ExtKind::Set { code } => ExtKind::Set { code },
        ExtKind::Call { fun, loop_, brk, until } => ExtKind::Call { fun, loop_, brk, until },
        ExtKind::Return { reset } => ExtKind::Return { reset },
        ExtKind::NavInit { lines } => ExtKind::NavInit { lines },
        ExtKind::Nav(nav) => ExtKind::Nav(nav),
    })
}

pub fn verify(fpe: Fpe) -> Result<Fps, CompileError> {
    let n = fpe.blocks.len();
    if n == 0 {
        return Err(CompileError::size("the plan has no block", None));
    }
    if n > MAX_BLOCKS {
        let span = fpe.blocks.get(MAX_BLOCKS).map(|b| b.span);
        return Err(CompileError::size(
            format!(
                "the plan has {n} blocks (including the implicit HOME block); at most {MAX_BLOCKS} are possible \
                 because Paparazzi stores block numbers in uint8_t (nav_block, last_block)"
            ),
            span,
        ));
    }
    let exceptions =
        |es: Vec<ExtException<usize>>| -> Result<Vec<ExtException<BlockNo>>, CompileError> {
            es.into_iter()
                .map(|e| {
                    Ok(ExtException { cond: e.cond, target: block_no(e.target, n)?, exec: e.exec })
                })
                .collect()
        };
    let mut blocks = Vec::with_capacity(n);
    for (i, b) in fpe.blocks.into_iter().enumerate() {
        if b.no != i {
            return Err(CompileError::size(
                format!("block '{}' is numbered {} at position {i}", b.name, b.no),
                Some(b.span),
            ));
        }
        let count = b.stages.len() + 1;
        if count > MAX_STAGES {
            return Err(CompileError::size(
                format!(
                    "block '{}' needs {count} stages (counting loop and end stages); at most {MAX_STAGES} are possible \
                     because Paparazzi stores stage numbers in uint8_t (nav_stage, last_stage)",
                    b.name
                ),
                Some(b.span),
            ));
        }
        if b.default_stage != b.stages.len() {
            return Err(CompileError::size(
                format!("block '{}': default stage is not last", b.name),
                Some(b.span),
            ));
        }
        let mut stages = Vec::with_capacity(b.stages.len());
        for (k, s) in b.stages.into_iter().enumerate() {
            if s.no != k {
                return Err(CompileError::size(
                    format!("block '{}': stage numbered {} at position {k}", b.name, s.no),
                    Some(b.span),
                ));
            }
            let kind = checked_kind(s.kind, n)?;
            // k < count <= 256, so the conversion cannot fail; keep it checked anyway.
            let no = u8::try_from(k)
                .map(StageNo)
                .map_err(|_| CompileError::size("stage number overflow", Some(b.span)))?;
            stages.push(ExtStage { no, depth: s.depth, kind });
        }
        let default_stage = u8::try_from(b.default_stage)
            .map(StageNo)
            .map_err(|_| CompileError::size("stage number overflow", Some(b.span)))?;
        blocks.push(ExtBlock {
            no: block_no(i, n)?,
            name: b.name,
            pre_call: b.pre_call,
            post_call: b.post_call,
            on_enter: b.on_enter,
            on_exit: b.on_exit,
            exceptions: exceptions(b.exceptions)?,
            stages,
            default_stage,
            span: b.span,
        });
    }
    let forbidden = fpe
        .forbidden
        .into_iter()
        .map(|f| {
            Ok(ExtForbidden {
                from: block_no(f.from, n)?,
                to: block_no(f.to, n)?,
                only_when: f.only_when,
            })
        })
        .collect::<Result<Vec<_>, CompileError>>()?;
    Ok(Fps(Ext { blocks, exceptions: exceptions(fpe.exceptions)?, forbidden }))
}
