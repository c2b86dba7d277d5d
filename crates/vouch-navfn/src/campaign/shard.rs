//! Shards: the part of a suite one process runs (`--shard I/N`, `--shard-by map|case`,
//! `--shard auto` from an array-job engine's environment).
//!
//! Ownership is a function of the map's key (its folder relative to the suite root, e.g.
//! `walls/25x25_50walls`) and the case number only, never of the rest of the suite: a shard
//! decides what is its own without reading, counting or even having the other maps, so a suite
//! generated shard by shard (`suite gen --shard I/N`) never has to exist on one machine.
//!
//! * every map has a **home shard**, `mix(FNV-1a-64(key)) mod N` (`mix` = the SplitMix64
//!   finaliser, so that similar names spread over all shards);
//! * `--shard-by map`: shard `I` runs every case of the maps whose home is `I`;
//! * `--shard-by case`: shard `I` runs case `k` of a map when `(home + k) mod N = I` — each map's
//!   cases go round-robin over the shards starting at its home, which balances suites made of a
//!   few large maps (case 0 always runs at home).

use serde::{Deserialize, Serialize};

use crate::core::numeric::Fnv1a;

/// What `--shard I/N` splits.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum ShardBy {
    /// Whole maps: a shard reads and transforms only its own maps.
    #[default]
    Map,
    /// Cases of every map, round-robin from the map's home shard.
    Case,
}

impl ShardBy {
    /// The name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            ShardBy::Map => "map",
            ShardBy::Case => "case",
        }
    }
}

/// One shard: `index` of `count`, split by `by`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// `I`, from 0.
    pub index: u32,
    /// `N`.
    pub count: u32,
    /// What is split.
    pub by: ShardBy,
}

/// A shard specification that cannot be used.
#[derive(Debug, PartialEq, Eq, thiserror::Error, miette::Diagnostic)]
pub enum ShardError {
    /// Not `I/N` with `0 ≤ I < N`.
    #[error("shard `{0}`: expected I/N with 0 <= I < N, e.g. 3/8, or `auto`")]
    #[diagnostic(code(navfn::E053))]
    Syntax(String),
    /// `--shard auto` found no array-job index, or an unusable one.
    #[error("--shard auto: {0}")]
    #[diagnostic(
        code(navfn::E054),
        help(
            "Slurm array jobs set SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT; Kubernetes \
             Indexed Jobs set JOB_COMPLETION_INDEX, and the shard count comes from \
             VOUCH_SHARD_COUNT (set it to the Job's `completions`)"
        )
    )]
    Environment(String),
}

/// The variable that gives the shard count of a Kubernetes Indexed Job (Kubernetes sets only
/// the index, `JOB_COMPLETION_INDEX`).
pub const SHARD_COUNT_VARIABLE: &str = "VOUCH_SHARD_COUNT";

impl Shard {
    /// The whole suite (shard 0 of 1).
    pub const ALL: Shard = Shard { index: 0, count: 1, by: ShardBy::Map };

    /// Shard `index` of `count`; one shard of one is always [`Shard::ALL`] (nothing is split).
    pub fn new(index: u32, count: u32, by: ShardBy) -> Result<Shard, ShardError> {
        if count == 0 || index >= count {
            return Err(ShardError::Syntax(format!("{index}/{count}")));
        }
        Ok(if count == 1 { Shard::ALL } else { Shard { index, count, by } })
    }

    /// Parse `I/N`.
    pub fn parse(s: &str, by: ShardBy) -> Result<Shard, ShardError> {
        let bad = || ShardError::Syntax(s.to_string());
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: u32 = i.trim().parse().map_err(|_| bad())?;
        let count: u32 = n.trim().parse().map_err(|_| bad())?;
        Shard::new(index, count, by).map_err(|_| bad())
    }

    /// `--shard auto`: the shard of this array task, from the environment (`var` looks a
    /// variable up). Slurm: `SLURM_ARRAY_TASK_ID − SLURM_ARRAY_TASK_MIN` (min 0 when unset) of
    /// `SLURM_ARRAY_TASK_COUNT`, step 1 only. Kubernetes Indexed Job: `JOB_COMPLETION_INDEX` of
    /// [`SHARD_COUNT_VARIABLE`].
    pub fn from_env(
        var: impl Fn(&str) -> Option<String>,
        by: ShardBy,
    ) -> Result<Shard, ShardError> {
        let num = |name: &str| -> Result<Option<u32>, ShardError> {
            match var(name) {
                None => Ok(None),
                Some(v) => v.trim().parse().map(Some).map_err(|_| {
                    ShardError::Environment(format!("{name}=`{v}` is not a non-negative integer"))
                }),
            }
        };
        let need = |name: &str, why: &str| -> Result<u32, ShardError> {
            num(name)?.ok_or_else(|| ShardError::Environment(format!("{name} is not set ({why})")))
        };
        let (index, count, engine) = if let Some(id) = num("SLURM_ARRAY_TASK_ID")? {
            let count = need("SLURM_ARRAY_TASK_COUNT", "Slurm array job")?;
            if num("SLURM_ARRAY_TASK_STEP")?.is_some_and(|s| s != 1) {
                return Err(ShardError::Environment(
                    "a Slurm array with a step other than 1 does not number shards 0..N-1".into(),
                ));
            }
            let min = num("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
            let index = id.checked_sub(min).ok_or_else(|| {
                ShardError::Environment(format!(
                    "SLURM_ARRAY_TASK_ID {id} below SLURM_ARRAY_TASK_MIN {min}"
                ))
            })?;
            (index, count, "Slurm")
        } else if let Some(index) = num("JOB_COMPLETION_INDEX")? {
            (index, need(SHARD_COUNT_VARIABLE, "Kubernetes Indexed Job")?, "Kubernetes")
        } else {
            return Err(ShardError::Environment(
                "neither SLURM_ARRAY_TASK_ID nor JOB_COMPLETION_INDEX is set".into(),
            ));
        };
        Shard::new(index, count, by).map_err(|_| {
            ShardError::Environment(format!("{engine} index {index} is not below count {count}"))
        })
    }

    /// The home shard of the map with key `key` among `count` shards.
    pub fn home(key: &str, count: u32) -> u32 {
        (mix(fnv1a(key.as_bytes())) % u64::from(count.max(1))) as u32
    }

    /// Whether this shard runs case `case` of a map whose home shard is `home`.
    pub fn owns_case(self, home: u32, case: u64) -> bool {
        match self.by {
            ShardBy::Map => home == self.index,
            ShardBy::Case => {
                let n = u64::from(self.count);
                (u64::from(home) + case % n) % n == u64::from(self.index)
            }
        }
    }

    /// Whether this shard must read the map with home `home`: its own maps when splitting by
    /// map; when splitting by case, every map (its number of cases says which cases are ours,
    /// and the file has to be read to know it).
    pub fn reads(self, home: u32) -> bool {
        self.by == ShardBy::Case || home == self.index
    }

    /// `I/N`.
    pub fn spec(self) -> String {
        format!("{}/{}", self.index, self.count)
    }
}

/// FNV-1a, 64 bits (the core's, as in the golden `pot_fnv`/`path_fnv`).
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h = Fnv1a::default();
    h.bytes(bytes);
    h.0
}

/// The SplitMix64 finaliser: every input bit reaches the low bits the modulo keeps.
fn mix(z: u64) -> u64 {
    super::rng::SplitMix64::mix(z)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| vars.iter().find(|(n, _)| *n == k).map(|(_, v)| v.to_string())
    }

    #[test]
    fn parse_accepts_i_of_n_only() {
        assert_eq!(
            Shard::parse("3/8", ShardBy::Case),
            Ok(Shard { index: 3, count: 8, by: ShardBy::Case })
        );
        assert_eq!(Shard::parse("0/1", ShardBy::Case), Ok(Shard::ALL));
        for bad in ["8/8", "x", "1/0", "-1/4", "1/2/3", ""] {
            assert!(Shard::parse(bad, ShardBy::Map).is_err(), "{bad}");
        }
    }

    #[test]
    fn fnv_and_home_are_the_documented_functions() {
        // FNV-1a-64 reference values (the algorithm's published test vectors).
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        // SplitMix64's first output for seed 0 is mix(0x9e3779b97f4a7c15).
        assert_eq!(mix(0x9e37_79b9_7f4a_7c15), 0xe220_a839_7b1d_cdaf);
        assert_eq!(Shard::home("anything", 1), 0);
    }

    #[test]
    fn every_case_has_exactly_one_owner_in_both_splits() {
        for by in [ShardBy::Map, ShardBy::Case] {
            let shards: Vec<Shard> = (0..5).map(|i| Shard::new(i, 5, by).expect("valid")).collect();
            for key in ["walls/a", "walls/b", "free/c", "x"] {
                let home = Shard::home(key, 5);
                assert!(shards[home as usize].reads(home));
                for k in 0..40u64 {
                    let owners: Vec<&Shard> =
                        shards.iter().filter(|s| s.owns_case(home, k)).collect();
                    assert_eq!(owners.len(), 1, "{key} case {k} {by:?}");
                    assert!(owners[0].reads(home));
                }
                assert!(shards[home as usize].owns_case(home, 0), "case 0 runs at home");
            }
        }
    }

    #[test]
    fn homes_spread_over_the_shards() {
        let mut per = [0u32; 8];
        for i in 0..8000 {
            per[Shard::home(&format!("walls/{i:04}_20x20_walls"), 8) as usize] += 1;
        }
        assert!(per.iter().all(|&n| (850..1150).contains(&n)), "{per:?}");
    }

    #[test]
    fn auto_reads_slurm_and_kubernetes() {
        let slurm = [("SLURM_ARRAY_TASK_ID", "5"), ("SLURM_ARRAY_TASK_COUNT", "16")];
        assert_eq!(Shard::from_env(env(&slurm), ShardBy::Map).expect("slurm").spec(), "5/16");
        let from_one = [
            ("SLURM_ARRAY_TASK_ID", "16"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_COUNT", "16"),
        ];
        assert_eq!(Shard::from_env(env(&from_one), ShardBy::Map).expect("slurm").spec(), "15/16");
        let k8s = [("JOB_COMPLETION_INDEX", "2"), ("VOUCH_SHARD_COUNT", "8")];
        let s = Shard::from_env(env(&k8s), ShardBy::Case).expect("k8s");
        assert_eq!((s.spec(), s.by), ("2/8".to_string(), ShardBy::Case));
        for bad in [
            &[][..],
            &[("JOB_COMPLETION_INDEX", "2")][..],
            &[("JOB_COMPLETION_INDEX", "8"), ("VOUCH_SHARD_COUNT", "8")][..],
            &[("SLURM_ARRAY_TASK_ID", "3")][..],
            &[("SLURM_ARRAY_TASK_ID", "x"), ("SLURM_ARRAY_TASK_COUNT", "4")][..],
            &[
                ("SLURM_ARRAY_TASK_ID", "2"),
                ("SLURM_ARRAY_TASK_COUNT", "4"),
                ("SLURM_ARRAY_TASK_STEP", "2"),
            ][..],
        ] {
            let e = Shard::from_env(env(bad), ShardBy::Map).expect_err("refused");
            assert!(matches!(e, ShardError::Environment(_)), "{bad:?}: {e}");
        }
    }
}
