//! What a report says about the suite it ran on, so that `report merge` can tell shards of one
//! suite from shards of another without trusting path names:
//!
//! * a **digest of every map it read**: SHA-256 of the test file's length (8 bytes, little
//!   endian), the test file's bytes and the map file's bytes;
//! * the suite's **fingerprint** and **size** (number of maps), learnt without reading any map:
//!   from the suite manifest that `suite gen` writes ([`MANIFEST`]; SHA-256 of its bytes, its
//!   map count), or else from the listing (SHA-256 of one line `key<TAB>test.txt size` per map,
//!   in walk order; the number of test files);
//! * the suite's **content hash** once every map is accounted for: SHA-256 of one line
//!   `key<TAB>map digest` per map in key order — computed by a run over the whole suite and
//!   by `report merge` from the union of its shards' digests, so the two must agree.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::maps::MapError;

/// The manifest `suite gen` writes at the root of every suite (and of every share of one).
pub const MANIFEST: &str = "vouch-suite.json";

/// SHA-256 digest of one map: test file length, test file, map file.
pub fn map_digest(test_txt: &[u8], map: &[u8]) -> String {
    let mut h = Sha256::new();
    h.update((test_txt.len() as u64).to_le_bytes());
    h.update(test_txt);
    h.update(map);
    hex(h)
}

fn hex(h: Sha256) -> String {
    hex::encode(h.finalize())
}

/// Where a suite's fingerprint and size come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum IdentityBasis {
    /// The test files found below the suite folder.
    #[default]
    Listing,
    /// The generator's manifest ([`MANIFEST`]): the folder may hold one share of the suite.
    Manifest,
}

/// One map as a report saw it.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MapDigest {
    /// Category folder.
    pub category: String,
    /// Cases in its test file.
    pub cases: u64,
    /// [`map_digest`] of its files.
    pub sha256: String,
}

/// The suite a report ran on.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SuiteIdentity {
    /// Where `fingerprint` and `maps_total` come from.
    pub basis: IdentityBasis,
    /// SHA-256 of the manifest or of the listing.
    pub fingerprint: String,
    /// Maps in the whole suite.
    pub maps_total: u64,
    /// SHA-256 of the whole suite's contents, when every map is in `maps`.
    pub content: Option<String>,
    /// Every map this report read, by key.
    pub maps: BTreeMap<String, MapDigest>,
}

impl SuiteIdentity {
    /// Set `content` when `maps` covers the whole suite, clear it otherwise.
    pub fn seal(&mut self) {
        self.content = (self.maps.len() as u64 == self.maps_total).then(|| {
            let mut h = Sha256::new();
            for (key, d) in &self.maps {
                h.update(format!("{key}\t{}\n", d.sha256).as_bytes());
            }
            hex(h)
        });
    }

    /// Cases of every map in `maps`.
    pub fn cases(&self) -> u64 {
        self.maps.values().map(|d| d.cases).fold(0, u64::saturating_add)
    }
}

/// The listing fingerprint, fed one map at a time in walk order.
#[derive(Default)]
pub struct ListingFingerprint {
    sha: Sha256,
    maps: u64,
}

impl ListingFingerprint {
    /// One more map.
    pub fn add(&mut self, key: &str, test_size: u64) {
        self.sha.update(format!("{key}\t{test_size}\n").as_bytes());
        self.maps += 1;
    }

    /// Maps seen so far.
    pub fn maps(&self) -> u64 {
        self.maps
    }

    /// The fingerprint.
    pub fn finish(self) -> String {
        hex(self.sha)
    }
}

/// What `suite gen` generated: enough to regenerate the suite, and its size.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SuiteManifest {
    /// Manifest format (1).
    pub format: u32,
    /// The generator's seed.
    pub seed: u64,
    /// Generated categories, in order.
    pub categories: Vec<String>,
    /// Maps per generated category.
    pub maps_per_category: u32,
    /// Map width/height range, border included.
    pub size: [u32; 2],
    /// Cases per generated map (at most).
    pub cases_per_map: usize,
    /// Imported nav2 maps: folder name and SHA-256 of the imported NavFn costs.
    pub ros_maps: Vec<(String, String)>,
    /// Cases per imported map (at most).
    pub ros_cases: usize,
    /// Maps in the whole suite.
    pub maps: u64,
}

impl SuiteManifest {
    /// The manifest's file text (pretty JSON, one trailing newline): the same options always
    /// give the same bytes.
    pub fn to_text(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).unwrap_or_default();
        s.push('\n');
        s
    }
}

/// SHA-256 of imported NavFn costs (the manifest's record of a nav2 map).
pub fn costs_digest(costs: &[u8]) -> String {
    let mut h = Sha256::new();
    h.update(costs);
    hex(h)
}

/// The manifest at the root of `dir`, if there is one: its fingerprint and map count.
pub fn read_manifest(dir: &Path) -> Result<Option<(String, u64)>, MapError> {
    let path = dir.join(MANIFEST);
    if !dir.is_dir() || !path.exists() {
        return Ok(None);
    }
    let bytes = std::fs::read(&path).map_err(|e| MapError::io(&path, e))?;
    let m: SuiteManifest = serde_json::from_slice(&bytes)
        .map_err(|e| MapError::file(&path, format!("not a suite manifest: {e}")))?;
    if m.format != 1 {
        return Err(MapError::file(
            &path,
            format!("suite manifest format {} (expected 1)", m.format),
        ));
    }
    let mut h = Sha256::new();
    h.update(&bytes);
    Ok(Some((hex(h), m.maps)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digests_are_sha256_of_the_documented_bytes() {
        // SHA-256 of 8 zero bytes (empty test file, empty map): a published-algorithm value
        // computed independently (`printf '\0\0\0\0\0\0\0\0' | sha256sum`).
        assert_eq!(
            map_digest(b"", b""),
            "af5570f5a1810b7af78caf4bc70a660f0df51e42baf91d4de5b2328de0e83dfc"
        );
        // The length prefix separates the two files.
        assert_ne!(map_digest(b"ab", b"c"), map_digest(b"a", b"bc"));
    }

    #[test]
    fn content_is_sealed_only_when_every_map_is_present() {
        let mut id = SuiteIdentity { maps_total: 2, ..SuiteIdentity::default() };
        id.maps
            .insert("a/x".into(), MapDigest { category: "a".into(), cases: 3, sha256: "1".into() });
        id.seal();
        assert_eq!(id.content, None);
        id.maps
            .insert("a/y".into(), MapDigest { category: "a".into(), cases: 4, sha256: "2".into() });
        id.seal();
        let mut h = Sha256::new();
        h.update(b"a/x\t1\na/y\t2\n");
        assert_eq!(id.content, Some(hex(h)));
        assert_eq!(id.cases(), 7);
    }
}
