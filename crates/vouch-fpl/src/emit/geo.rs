//! Coordinate conversions of upstream's generator (GENERATOR_FACTS.md section 10): WGS84,
//! UTM by the IGN complex-series transverse Mercator (5 terms), ECEF, local NED, with the same
//! constants (eccentricity given as a literal, not derived) and the same operation order, so
//! that results printed with `%.2f`/`%.1f` match upstream on a correctly rounded libm.

use std::f64::consts::PI;

pub const WGS84_A: f64 = 6378137.0;
pub const WGS84_DF: f64 = 0.0033528106647474805;
pub const WGS84_E: f64 = 0.08181919106;
const K0: f64 = 0.9996;
const XS: f64 = 500000.0;

/// A geodetic position in radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geo {
    pub lat: f64,
    pub lon: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Utm {
    pub x: f64,
    pub y: f64,
    pub zone: i32,
}

/// Degrees to radians, multiplying first (`x*pi/180`).
pub fn rad_of_deg(x: f64) -> f64 {
    x * PI / 180.0
}

pub fn deg_of_rad(x: f64) -> f64 {
    x * 180.0 / PI
}

fn norm_angle(l: f64) -> f64 {
    if l >= PI {
        l - 2.0 * PI
    } else if l < -PI {
        l + 2.0 * PI
    } else {
        l
    }
}

pub fn geo_of_deg(lat: f64, lon: f64) -> Geo {
    Geo { lat: rad_of_deg(lat), lon: norm_angle(rad_of_deg(lon)) }
}

/// Truncation to 1e7 degrees (`Int64.of_float`), as `NAV_LAT0` and the LLA tables print.
pub fn e7_of_rad(r: f64) -> i64 {
    (1e7 * deg_of_rad(r)) as i64
}

#[derive(Debug, Clone, Copy)]
struct Cx {
    re: f64,
    im: f64,
}

impl Cx {
    fn add(self, o: Cx) -> Cx {
        Cx { re: self.re + o.re, im: self.im + o.im }
    }
    fn sub(self, o: Cx) -> Cx {
        Cx { re: self.re - o.re, im: self.im - o.im }
    }
    fn scal(self, a: f64) -> Cx {
        Cx { re: self.re * a, im: self.im * a }
    }
    /// Multiplication by i.
    fn i(self) -> Cx {
        Cx { re: -self.im, im: self.re }
    }
    fn exp(self) -> Cx {
        let e = self.re.exp();
        Cx { re: e * self.im.cos(), im: e * self.im.sin() }
    }
    /// sin z = i * (-1/2) * (exp(iz) - exp(-iz)), the formula upstream uses.
    fn sin(self) -> Cx {
        let iz = self.i();
        iz.exp().sub(iz.scal(-1.0).exp()).scal(-0.5).i()
    }
}

fn latitude_isometrique(phi: f64, e: f64) -> f64 {
    (PI / 4.0 + phi / 2.0).tan().ln()
        - e / 2.0 * ((1.0 + e * phi.sin()) / (1.0 - e * phi.sin())).ln()
}

fn inverse_latitude_isometrique(lat: f64, e: f64, epsilon: f64) -> f64 {
    let exp_l = lat.exp();
    let pi_2 = PI / 2.0;
    let mut phi = 2.0 * exp_l.atan() - pi_2;
    // The iteration converges quadratically; the cap only guards against NaN inputs.
    for _ in 0..100 {
        let sin_phi = e * phi.sin();
        let next = 2.0 * (((1.0 + sin_phi) / (1.0 - sin_phi)).powf(e / 2.0) * exp_l).atan() - pi_2;
        if (next - phi).abs() < epsilon {
            return next;
        }
        phi = next;
    }
    phi
}

const PROJ: [[f64; 5]; 5] = [
    [1.0, -1.0 / 4.0, -3.0 / 64.0, -5.0 / 256.0, -175.0 / 16384.0],
    [0.0, 1.0 / 8.0, -1.0 / 96.0, -9.0 / 1024.0, -901.0 / 184320.0],
    [0.0, 0.0, 13.0 / 768.0, 17.0 / 5120.0, -311.0 / 737280.0],
    [0.0, 0.0, 0.0, 61.0 / 15360.0, 899.0 / 430080.0],
    [0.0, 0.0, 0.0, 0.0, 49561.0 / 41287680.0],
];

const PROJ_INV: [[f64; 5]; 5] = [
    [1.0, -1.0 / 4.0, -3.0 / 64.0, -5.0 / 256.0, -175.0 / 16384.0],
    [0.0, 1.0 / 8.0, 1.0 / 48.0, 7.0 / 2048.0, 1.0 / 61440.0],
    [0.0, 0.0, 1.0 / 768.0, 3.0 / 1280.0, 559.0 / 368640.0],
    [0.0, 0.0, 0.0, 17.0 / 30720.0, 283.0 / 430080.0],
    [0.0, 0.0, 0.0, 0.0, 4397.0 / 41287680.0],
];

fn serie5(cc: &[[f64; 5]; 5], e: f64) -> [f64; 5] {
    let mut ee = [0.0; 5];
    for (j, v) in ee.iter_mut().enumerate() {
        *v = e.powf((2 * j) as f64);
    }
    let mut out = [0.0; 5];
    for (i, row) in cc.iter().enumerate() {
        let mut x = 0.0;
        for j in 0..5 {
            x += row[j] * ee[j];
        }
        out[i] = x;
    }
    out
}

/// UTM of a position; `zone` forces the zone (waypoints use the reference's zone).
pub fn utm_of(geo: Geo, zone: Option<i32>) -> Utm {
    let e = WGS84_E;
    let n = K0 * WGS84_A;
    let c = serie5(&PROJ, e);
    let lambda_deg = deg_of_rad(geo.lon).floor() as i32;
    let (zone, lambda_c) = match zone {
        Some(z) => (z, rad_of_deg(f64::from(6 * z - 183))),
        None => {
            let z = (lambda_deg + 180) / 6 + 1;
            let central = lambda_deg - ((lambda_deg % 6) + 6) % 6 + 3;
            (z, rad_of_deg(f64::from(central)))
        }
    };
    let ll = latitude_isometrique(geo.lat, e);
    let dl = geo.lon - lambda_c;
    let phi_p = (dl.sin() / ll.cosh()).asin();
    let ll_p = latitude_isometrique(phi_p, 0.0);
    let lambda_p = (ll.sinh() / dl.cos()).atan();
    let z = Cx { re: lambda_p, im: ll_p };
    let mut zp = z.scal(c[0]);
    for (k, ck) in c.iter().enumerate().skip(1) {
        zp = zp.add(z.scal((2 * k) as f64).sin().scal(*ck));
    }
    let zp = zp.scal(n);
    Utm { x: XS + zp.im, y: zp.re, zone }
}

pub fn of_utm(u: Utm) -> Geo {
    let e = WGS84_E;
    let n = K0 * WGS84_A;
    let c = serie5(&PROJ_INV, e);
    let lambda_c = rad_of_deg(f64::from(6 * u.zone - 183));
    let zp = Cx { re: u.y - 0.0, im: u.x - XS }.scal(1.0 / n / c[0]);
    let mut z = zp;
    for (k, ck) in c.iter().enumerate().skip(1) {
        z = z.sub(zp.scal((2 * k) as f64).sin().scal(*ck));
    }
    let (ll, lls) = (z.re, z.im);
    let lambda = lambda_c + (lls.sinh() / ll.cos()).atan();
    let phi_p = (ll.sin() / lls.cosh()).asin();
    let ll = latitude_isometrique(phi_p, 0.0);
    let phi = inverse_latitude_isometrique(ll, e, 1e-11);
    Geo { lat: phi, lon: norm_angle(lambda) }
}

pub fn ecef_of_geo(g: Geo, h: f64) -> [f64; 3] {
    let e2 = 2.0 * WGS84_DF - WGS84_DF * WGS84_DF;
    let (sin_lat, cos_lat, cos_lon) = (g.lat.sin(), g.lat.cos(), g.lon.cos());
    let chi = (1.0 - e2 * sin_lat * sin_lat).sqrt();
    let a_chi = WGS84_A / chi;
    [
        (a_chi + h) * cos_lat * cos_lon,
        (a_chi + h) * cos_lat * g.lon.sin(),
        (a_chi * (1.0 - e2) + h) * sin_lat,
    ]
}

/// Closed-form ECEF to geodetic (upstream's `geo_of_ecef`).
pub fn geo_of_ecef(p: [f64; 3]) -> (Geo, f64) {
    let df = WGS84_DF;
    let a = WGS84_A;
    let e2 = 2.0 * df - df * df;
    let ep2 = df * (2.0 - df) / (1.0 - df).powf(2.0);
    let b = a * (1.0 - df);
    let (x, y, z) = (p[0], p[1], p[2]);
    let z2 = z.powf(2.0);
    let r2 = x.powf(2.0) + y.powf(2.0);
    let r = r2.sqrt();
    let e_2 = a.powf(2.0) - b.powf(2.0);
    let f = 54.0 * b.powf(2.0) * z2;
    let g = r2 + (1.0 - e2) * z2 - e2 * e_2;
    let c = (e2 * e2 * f * r2) / g.powf(3.0);
    let s = (1.0 + c + (c.powf(2.0) + 2.0 * c).sqrt()).powf(1.0 / 3.0);
    let pp = f / (3.0 * (s + 1.0 / s + 1.0).powf(2.0) * g.powf(2.0));
    let q = (1.0 + 2.0 * e2 * e2 * pp).sqrt();
    let r0 = -(e2 * pp * r) / (1.0 + q)
        + ((a.powf(2.0) / 2.0) * (1.0 + 1.0 / q)
            - ((1.0 - e2) * pp * z2) / (q * (1.0 + q))
            - pp * r2 / 2.0)
            .sqrt();
    let tmp = (r - e2 * r0).powf(2.0);
    let u = (tmp + z2).sqrt();
    let v = (tmp + (1.0 - e2) * z2).sqrt();
    let z0 = (b.powf(2.0) * z) / (a * v);
    let h = u * (1.0 - b.powf(2.0) / (a * v));
    let phi = ((z + ep2 * z0) / r).atan();
    let lambda = y.atan2(x);
    (Geo { lat: phi, lon: lambda }, h)
}

/// NED of `p` in the tangent frame at `r` (both ECEF), rotation from `r`'s geodetic position.
pub fn ned_of_ecef(r: [f64; 3], p: [f64; 3]) -> [f64; 3] {
    let (g, _) = geo_of_ecef(r);
    let (sl, cl, sp, cp) = (g.lon.sin(), g.lon.cos(), g.lat.sin(), g.lat.cos());
    let (dx, dy, dz) = (p[0] - r[0], p[1] - r[1], p[2] - r[2]);
    let e = -sl * dx + cl * dy;
    let n = -sp * cl * dx - sp * sl * dy + cp * dz;
    let u = cp * cl * dx + cp * sl * dy + sp * dz;
    [n, e, -u]
}

/// ECEF of a NED offset in the tangent frame at `r` (used for LTP-frame waypoints).
pub fn ecef_of_ned(r: [f64; 3], ned: [f64; 3]) -> [f64; 3] {
    let (g, _) = geo_of_ecef(r);
    let (sl, cl, sp, cp) = (g.lon.sin(), g.lon.cos(), g.lat.sin(), g.lat.cos());
    let (n, e, u) = (ned[0], ned[1], -ned[2]);
    [
        -sl * e - cl * sp * n + cl * cp * u + r[0],
        cl * e - sl * sp * n + cp * sl * u + r[1],
        cp * n + sp * u + r[2],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utm_round_trip_is_sub_millimetre() {
        let g = geo_of_deg(43.46223, 1.27289);
        let u = utm_of(g, None);
        assert_eq!(u.zone, 31);
        let back = of_utm(u);
        assert!((back.lat - g.lat).abs() < 1e-9 && (back.lon - g.lon).abs() < 1e-9);
    }

    #[test]
    fn ned_of_the_reference_itself_is_zero() {
        let r = ecef_of_geo(geo_of_deg(43.5, 1.4), 150.0);
        let n = ned_of_ecef(r, r);
        assert!(n.iter().all(|v| v.abs() < 1e-9));
        let up = ecef_of_geo(geo_of_deg(43.5, 1.4), 160.0);
        let n = ned_of_ecef(r, up);
        assert!((n[2] + 10.0).abs() < 1e-3, "{n:?}");
    }
}
