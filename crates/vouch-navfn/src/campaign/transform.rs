//! Metamorphic transforms of a suite map and its cases: the dihedral symmetries of the grid
//! (rotations by 90/180/270°, mirrors) and embedding in a larger frame of obstacles.
//! The relations that must hold between runs are in `metamorphic.rs`.

use crate::campaign::grid::{Case, OBSTACLE, SuiteMap};

/// A transform of a map and its cases.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Transform {
    /// Clockwise rotation by 90° (on screen, with y pointing down).
    Rot90,
    /// Rotation by 180°.
    Rot180,
    /// Clockwise rotation by 270°.
    Rot270,
    /// Left–right mirror (x → W−1−x).
    MirrorX,
    /// Top–bottom mirror (y → H−1−y).
    MirrorY,
    /// Embed in a frame of `pad` obstacle cells on every side (offset `pad` in x and y).
    Embed {
        /// Frame width in cells.
        pad: u32,
    },
}

impl std::str::FromStr for Transform {
    type Err = String;
    /// Parses a [`Transform::label`].
    fn from_str(s: &str) -> Result<Self, String> {
        Ok(match s {
            "rot90" => Transform::Rot90,
            "rot180" => Transform::Rot180,
            "rot270" => Transform::Rot270,
            "mirror_x" => Transform::MirrorX,
            "mirror_y" => Transform::MirrorY,
            _ => match s.strip_prefix("embed").and_then(|p| p.parse().ok()) {
                Some(pad) => Transform::Embed { pad },
                None => return Err(format!("unknown transform `{s}`")),
            },
        })
    }
}

impl Transform {
    /// The transforms every campaign case is run under.
    pub const ALL_BASIC: [Transform; 6] = [
        Transform::Rot90,
        Transform::Rot180,
        Transform::Rot270,
        Transform::MirrorX,
        Transform::MirrorY,
        Transform::Embed { pad: 3 },
    ];

    /// The name in relation names (`rot90`, `mirror_x`, `embed3`, …).
    pub fn label(self) -> String {
        match self {
            Transform::Rot90 => "rot90".into(),
            Transform::Rot180 => "rot180".into(),
            Transform::Rot270 => "rot270".into(),
            Transform::MirrorX => "mirror_x".into(),
            Transform::MirrorY => "mirror_y".into(),
            Transform::Embed { pad } => format!("embed{pad}"),
        }
    }

    /// Size of the transformed map.
    pub fn size(self, w: u32, h: u32) -> (u32, u32) {
        match self {
            Transform::Rot90 | Transform::Rot270 => (h, w),
            Transform::Rot180 | Transform::MirrorX | Transform::MirrorY => (w, h),
            Transform::Embed { pad } => (w + 2 * pad, h + 2 * pad),
        }
    }

    /// Where cell `(x, y)` of a `w×h` map lands.
    pub fn point(self, w: u32, h: u32, x: u32, y: u32) -> (u32, u32) {
        match self {
            // Clockwise on screen: the left column becomes the top row.
            Transform::Rot90 => (h - 1 - y, x),
            Transform::Rot180 => (w - 1 - x, h - 1 - y),
            Transform::Rot270 => (y, w - 1 - x),
            Transform::MirrorX => (w - 1 - x, y),
            Transform::MirrorY => (x, h - 1 - y),
            Transform::Embed { pad } => (x + pad, y + pad),
        }
    }

    /// Where a float path point lands (the same affine map on continuous coordinates, cells
    /// being identified with their integer corner coordinates as in NavFn).
    pub fn point_f(self, w: u32, h: u32, p: (f32, f32)) -> (f64, f64) {
        let (x, y) = (f64::from(p.0), f64::from(p.1));
        let (wm, hm) = (f64::from(w) - 1.0, f64::from(h) - 1.0);
        match self {
            Transform::Rot90 => (hm - y, x),
            Transform::Rot180 => (wm - x, hm - y),
            Transform::Rot270 => (y, wm - x),
            Transform::MirrorX => (wm - x, y),
            Transform::MirrorY => (x, hm - y),
            Transform::Embed { pad } => (x + f64::from(pad), y + f64::from(pad)),
        }
    }

    /// Transform map and cases.
    pub fn apply(self, m: &SuiteMap) -> SuiteMap {
        let (w2, h2) = self.size(m.width, m.height);
        let mut out = SuiteMap {
            category: m.category.clone(),
            name: format!("{}@{}", m.name, self.label()),
            width: w2,
            height: h2,
            costs: vec![OBSTACLE; (w2 * h2) as usize],
            cases: Vec::with_capacity(m.cases.len()),
        };
        for y in 0..m.height {
            for x in 0..m.width {
                let (a, b) = self.point(m.width, m.height, x, y);
                out.set(a, b, m.get(x, y));
            }
        }
        for c in &m.cases {
            let (a0, b0) = self.point(m.width, m.height, c.x0, c.y0);
            let (a1, b1) = self.point(m.width, m.height, c.x1, c.y1);
            out.cases.push(Case::new(a0, b0, a1, b1));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> SuiteMap {
        let mut m = SuiteMap::filled("t", "m", 6, 5, 50);
        m.set(1, 1, 99);
        m.set(3, 2, 200);
        m.cases.push(Case::new(1, 1, 4, 3));
        m
    }

    #[test]
    fn four_quarter_turns_are_identity() {
        let m = sample();
        let r = Transform::Rot90
            .apply(&Transform::Rot90.apply(&Transform::Rot90.apply(&Transform::Rot90.apply(&m))));
        assert_eq!(r.costs, m.costs);
        assert_eq!(r.cases, m.cases);
        assert_eq!((r.width, r.height), (6, 5));
    }

    #[test]
    fn rot90_then_rot270_and_mirrors_are_involutive() {
        let m = sample();
        assert_eq!(Transform::Rot270.apply(&Transform::Rot90.apply(&m)).costs, m.costs);
        assert_eq!(Transform::MirrorX.apply(&Transform::MirrorX.apply(&m)).costs, m.costs);
        assert_eq!(
            Transform::Rot180.apply(&m).costs,
            Transform::MirrorX.apply(&Transform::MirrorY.apply(&m)).costs
        );
    }

    #[test]
    fn rot90_moves_the_marked_cell_clockwise() {
        let m = sample();
        let r = Transform::Rot90.apply(&m);
        // (1,1) in a 6x5 map → (5-1-1, 1) = (3, 1) in the 5x6 result.
        assert_eq!(r.get(3, 1), 99);
        assert_eq!(r.cases[0], Case::new(3, 1, 1, 4));
        let f = Transform::Rot90.point_f(6, 5, (1.0, 1.0));
        assert_eq!(f, (3.0, 1.0));
    }

    #[test]
    fn embed_pads_with_obstacles() {
        let m = sample();
        let e = Transform::Embed { pad: 2 }.apply(&m);
        assert_eq!((e.width, e.height), (10, 9));
        assert_eq!(e.get(3, 3), 99);
        assert_eq!(e.get(0, 0), OBSTACLE);
        assert_eq!(e.get(2, 2), OBSTACLE); // the old border
        assert_eq!(e.cases[0], Case::new(3, 3, 6, 5));
    }
}
