//! The robot's footprint as nav2's costmap takes it: a `robot_radius` (a 16-gon) or a
//! `footprint` polygon string, padded by `footprint_padding`, and the inscribed radius the
//! inflation layer uses.
//!
//! Rounding follows nav2 (navigation2 `a3a97043ee93`): polygon coordinates are read as floats
//! then widened, the radius polygon's vertices are `cos/sin(i·2π/16)·r` in double, the padding
//! is the float `0.01f` widened, and the inscribed radius is the smallest distance from the
//! origin to a vertex or an edge (`hypot`, the projection clamped to the segment).

use super::CostmapError;

/// nav2's default `footprint_padding`: declared as the float `0.01f`, stored in a float member
/// and widened where it is added.
pub const DEFAULT_PADDING: f64 = 0.01f32 as f64;

/// How the footprint was given.
#[derive(Clone, Debug, PartialEq)]
pub enum FootprintSpec {
    /// `robot_radius` in metres.
    Radius(f64),
    /// `footprint` vertices in metres (robot frame), as floats widened to double.
    Polygon(Vec<[f64; 2]>),
}

/// A robot footprint: the polygon in the robot frame after padding.
#[derive(Clone, Debug, PartialEq)]
pub struct Footprint {
    /// What the user gave.
    pub spec: FootprintSpec,
    /// The padding added (metres).
    pub padding: f64,
    /// Vertices after padding, robot frame (x forward), metres.
    pub points: Vec<[f64; 2]>,
}

impl Footprint {
    /// The footprint of a circular robot (`robot_radius`), padded.
    pub fn from_radius(radius: f64, padding: f64) -> Result<Self, CostmapError> {
        if !radius.is_finite() || radius < 0.0 {
            return Err(CostmapError::Parameter { name: "robot_radius", value: radius });
        }
        let points = (0..16)
            .map(|i| {
                let angle = f64::from(i * 2) * std::f64::consts::PI / 16.0;
                [angle.cos() * radius, angle.sin() * radius]
            })
            .collect();
        Ok(Self::padded(FootprintSpec::Radius(radius), points, padding))
    }

    /// The footprint of a `footprint` parameter string `[[x, y], [x, y], …]` (at least three
    /// points), padded.
    pub fn from_polygon_str(text: &str, padding: f64) -> Result<Self, CostmapError> {
        let points = parse_polygon(text)?;
        Ok(Self::padded(FootprintSpec::Polygon(points.clone()), points, padding))
    }

    fn padded(spec: FootprintSpec, mut points: Vec<[f64; 2]>, padding: f64) -> Self {
        for p in &mut points {
            p[0] += sign0(p[0]) * padding;
            p[1] += sign0(p[1]) * padding;
        }
        Footprint { spec, padding, points }
    }

    /// The inscribed radius: the smallest distance from the robot origin to a vertex or an edge
    /// of the padded polygon (what `LayeredCostmap::setFootprint` computes).
    pub fn inscribed_radius(&self) -> f64 {
        self.min_max_distances().0
    }

    /// The circumscribed radius: the largest distance from the origin to a vertex or an edge.
    pub fn circumscribed_radius(&self) -> f64 {
        self.min_max_distances().1
    }

    fn min_max_distances(&self) -> (f64, f64) {
        let pts = &self.points;
        if pts.len() <= 2 {
            return (f64::MAX, 0.0);
        }
        let mut min = f64::MAX;
        let mut max = 0.0f64;
        for (i, a) in pts.iter().enumerate() {
            let b = pts[(i + 1) % pts.len()];
            let vertex = (a[0] - 0.0).hypot(a[1] - 0.0);
            let edge = distance_to_segment([0.0, 0.0], *a, b);
            min = min.min(vertex.min(edge));
            max = max.max(vertex.max(edge));
        }
        (min, max)
    }

    /// The polygon placed at `(x, y)` with heading `yaw`, in double as nav2's
    /// `transformFootprint`.
    pub fn oriented(&self, x: f64, y: f64, yaw: f64) -> Vec<[f64; 2]> {
        let (s, c) = (yaw.sin(), yaw.cos());
        self.points.iter().map(|p| [x + (p[0] * c - p[1] * s), y + (p[0] * s + p[1] * c)]).collect()
    }
}

fn sign0(x: f64) -> f64 {
    if x < 0.0 {
        -1.0
    } else if x > 0.0 {
        1.0
    } else {
        0.0
    }
}

/// Distance from `p` to the segment `a`–`b`: the projection parameter clamped to [0, 1], in the
/// order of operations of nav2's `distanceToLine`.
pub fn distance_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (ax, ay) = (p[0] - a[0], p[1] - a[1]);
    let (cx, cy) = (b[0] - a[0], b[1] - a[1]);
    let dot = ax * cx + ay * cy;
    let len_sq = cx * cx + cy * cy;
    let param = dot / len_sq;
    let (xx, yy) = if param < 0.0 {
        (a[0], a[1])
    } else if param > 1.0 {
        (b[0], b[1])
    } else {
        (a[0] + param * cx, a[1] + param * cy)
    };
    (xx - p[0]).hypot(yy - p[1])
}

/// Parse `[[x, y], …]`: brackets, commas, blanks and numbers (read as `f32` like nav2's
/// parser); every inner list has two numbers; at least three points.
fn parse_polygon(text: &str) -> Result<Vec<[f64; 2]>, CostmapError> {
    let err = |offset: usize, msg: &str| CostmapError::Footprint {
        text: text.to_string(),
        offset,
        msg: msg.to_string(),
    };
    let mut points = Vec::new();
    let mut current: Vec<f64> = Vec::new();
    let mut depth = 0u32;
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'[' => {
                depth += 1;
                if depth > 2 {
                    return Err(err(i, "lists nested deeper than [[x, y], …]"));
                }
                current.clear();
                i += 1;
            }
            b']' => {
                if depth == 0 {
                    return Err(err(i, "more `]` than `[`"));
                }
                depth -= 1;
                if depth == 1 {
                    if current.len() != 2 {
                        return Err(err(i, "a point must be two numbers [x, y]"));
                    }
                    points.push([current[0], current[1]]);
                }
                i += 1;
            }
            b',' | b' ' | b'\t' => i += 1,
            _ => {
                if depth != 2 {
                    return Err(err(i, "a number outside a point [x, y]"));
                }
                let end = bytes[i..]
                    .iter()
                    .position(|b| matches!(b, b',' | b' ' | b'\t' | b'[' | b']'))
                    .map_or(bytes.len(), |n| i + n);
                let value: f32 = text[i..end]
                    .parse()
                    .ok()
                    .filter(|v: &f32| v.is_finite())
                    .ok_or_else(|| err(i, "not a finite number"))?;
                current.push(f64::from(value));
                i = end;
            }
        }
    }
    if depth != 0 {
        return Err(err(text.len(), "unterminated list"));
    }
    if points.len() < 3 {
        return Err(err(0, "a footprint needs at least three points"));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_footprint_inscribed_and_circumscribed() {
        let f = Footprint::from_polygon_str(
            "[[0.5, 0.5], [0.5, -0.5], [-0.5, -0.5], [-0.5, 0.5]]",
            0.0,
        )
        .unwrap();
        assert_eq!(f.inscribed_radius(), 0.5);
        assert_eq!(f.circumscribed_radius(), 0.5f64.hypot(0.5));
    }

    #[test]
    fn radius_polygon_inscribed_is_cos_pi_16() {
        let f = Footprint::from_radius(1.0, 0.0).unwrap();
        let expect = (std::f64::consts::PI / 16.0).cos();
        assert!((f.inscribed_radius() - expect).abs() < 1e-12);
    }

    proptest::proptest! {
        /// Any string: a footprint or a located error, never a panic; the offset is in it.
        #[test]
        fn any_string_parses_or_is_located(text in "[\\[\\], 0-9.eE+x-]{0,40}") {
            match Footprint::from_polygon_str(&text, 0.01) {
                Ok(f) => proptest::prop_assert!(f.points.len() >= 3),
                Err(CostmapError::Footprint { offset, .. }) => proptest::prop_assert!(offset <= text.len()),
                Err(e) => proptest::prop_assert!(false, "{e}"),
            }
        }
    }

    #[test]
    fn bad_polygons_are_located() {
        for (text, offset) in [
            ("[[1, 2], [3]]", 11),
            ("[[1, 2], [3, x], [0, 0]]", 13),
            ("[[1,2],[2,3]]", 0),
            ("[[é,1],[2,3],[4,5]]", 2),
            ("[[1,2],[3,4],[5,6]", 18),
        ] {
            match Footprint::from_polygon_str(text, 0.0) {
                Err(CostmapError::Footprint { offset: o, .. }) => assert_eq!(o, offset, "{text}"),
                other => panic!("{text}: {other:?}"),
            }
        }
    }
}
