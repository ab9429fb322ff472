//! Simulated range sensors: a pinhole RGB-D camera and an omnidirectional (lidar-like) colour
//! scanner, both ray-cast against the [`Heightfield`].
//!
//! **Geometry.** The sensor sits `height` metres above the terrain under the robot centre and looks
//! along the body heading turned by `yaw_deg` (a rear camera: 180°). The RGB-D camera casts one
//! ray through the centre of each pixel of a `width × height` image whose tangent-plane extent is
//! `tan(hfov/2) × tan(vfov/2)`, with the optical axis tilted down by `tilt_deg`. The
//! omnidirectional sensor casts `columns` azimuths over 360° times `rows` elevations spread evenly
//! from `min_elevation_deg` to `max_elevation_deg`.
//!
//! **Noise** (decision 2). A hit at true range r is moved along its ray by a Gaussian error of
//! standard deviation σ = sqrt(σ_d² + (k_d · r²)²); each colour channel of the hit cell gets
//! Gaussian noise of σ_c (0–255 scale), rounded and clamped. Only hits within the sensor's range
//! (true range) are returned, in the world frame, with the cloud's `origin` at the sensor.
//!
//! **Determinism.** Rays are cast in parallel (rayon): a camera's over fixed chunks of
//! [`RAYS_PER_CHUNK`] rays, an omnidirectional sensor's by azimuth column
//! ([`Heightfield::cast_column`], each ray's hit exactly as if cast alone). Each chunk of rays, in
//! ray order, draws its noise from its own ChaCha8 stream keyed by (simulation seed, scan counter,
//! chunk index), so a scan is bit-identical whatever the thread count.

use rand::RngExt;
use rand::rngs::ChaCha8Rng;
use rand_distr::StandardNormal;
use rayon::prelude::*;
use strider_core::{ColoredPoint, Point3, PointCloud, Pose2, Rgb8};
use strider_scenario::{SensorKind, SensorSpec, SimParams};

use crate::error::SimError;
use crate::heightfield::Heightfield;
use crate::seed::{key, stream};

/// Rays per parallel work item (and per noise stream). Fixed, so the output does not depend on
/// the thread count.
pub const RAYS_PER_CHUNK: usize = 1024;

/// The sensor-noise parameters of a scan (a subset of [`SimParams`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScanNoise {
    /// Range-independent depth noise σ_d, metres.
    pub depth_sigma: f64,
    /// Range-dependent depth noise factor k_d, 1/metre.
    pub depth_k: f64,
    /// Colour noise per channel, standard deviation (0–255 scale).
    pub color_sigma: f64,
}

impl ScanNoise {
    /// No noise at all.
    pub const NONE: ScanNoise = ScanNoise {
        depth_sigma: 0.0,
        depth_k: 0.0,
        color_sigma: 0.0,
    };

    /// The noise of a scenario's simulator parameters.
    pub fn from_params(p: &SimParams) -> Self {
        Self {
            depth_sigma: p.depth_sigma,
            depth_k: p.depth_k,
            color_sigma: p.color_sigma,
        }
    }

    /// Depth standard deviation at true range `r`: sqrt(σ_d² + (k_d · r²)²) (decision 2).
    #[inline]
    pub fn depth_std(&self, r: f64) -> f64 {
        // Not `hypot`: both terms are far from overflow, and libm's hypot was about a fifth of
        // a scan's noise instructions (callgrind).
        let b = self.depth_k * r * r;
        (self.depth_sigma * self.depth_sigma + b * b).sqrt()
    }
}

/// A range sensor with its rays precomputed in the body frame.
#[derive(Clone, Debug)]
pub struct RangeSensor {
    spec: SensorSpec,
    /// Unit ray directions in the body frame (x forward, y left, z up), mounting yaw and tilt
    /// applied.
    dirs: Vec<[f64; 3]>,
}

impl RangeSensor {
    /// Builds the sensor of `spec` after checking it ([`SensorSpec::validate`], which bounds
    /// the number of rays); `name` (e.g. `robot.sensors[0]`) prefixes error messages.
    pub fn new(spec: &SensorSpec, name: &str) -> Result<Self, SimError> {
        spec.validate(name)?;
        let yaw = spec.yaw_deg.to_radians();
        let dirs = match spec.kind {
            SensorKind::RgbD {
                hfov_deg,
                vfov_deg,
                width,
                height,
                tilt_deg,
            } => pinhole_rays(hfov_deg, vfov_deg, (width, height), tilt_deg, yaw),
            SensorKind::Omni {
                min_elevation_deg,
                max_elevation_deg,
                columns,
                rows,
            } => omni_rays((min_elevation_deg, max_elevation_deg), columns, rows, yaw),
        };
        Ok(Self {
            spec: spec.clone(),
            dirs,
        })
    }

    /// The sensor's specification.
    pub fn spec(&self) -> &SensorSpec {
        &self.spec
    }

    /// Number of rays per scan.
    pub fn ray_count(&self) -> usize {
        self.dirs.len()
    }

    /// Unit ray directions in the body frame (x forward, y left, z up).
    pub fn body_directions(&self) -> &[[f64; 3]] {
        &self.dirs
    }

    /// Sensor position for a robot at `pose` standing on terrain of elevation `ground_z`.
    pub fn origin(&self, pose: Pose2, ground_z: f64) -> Point3 {
        Point3::new(pose.x, pose.y, ground_z + self.spec.height)
    }

    /// True when the world-frame direction `dir` (any length) from the sensor lies inside the
    /// field of view for a robot heading `yaw` (pinhole: inside the image rectangle in the
    /// tangent plane; omni: between the elevation limits).
    pub fn in_fov(&self, yaw: f64, dir: [f64; 3]) -> bool {
        let n = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
        if !(n > 0.0 && n.is_finite()) {
            return false;
        }
        let (x, y, z) = (dir[0] / n, dir[1] / n, dir[2] / n);
        match self.spec.kind {
            SensorKind::RgbD {
                hfov_deg,
                vfov_deg,
                tilt_deg,
                ..
            } => {
                let (sy, cy) = (yaw + self.spec.yaw_deg.to_radians()).sin_cos();
                // World → mounting frame (undo yaw), then undo the tilt.
                let (bx, by) = (x * cy + y * sy, -x * sy + y * cy);
                let (st, ct) = tilt_deg.to_radians().sin_cos();
                let (cx, cz) = (bx * ct - z * st, bx * st + z * ct);
                cx > 0.0
                    && (by / cx).abs() <= (hfov_deg.to_radians() / 2.0).tan()
                    && (cz / cx).abs() <= (vfov_deg.to_radians() / 2.0).tan()
            }
            SensorKind::Omni {
                min_elevation_deg,
                max_elevation_deg,
                ..
            } => {
                let e = z.clamp(-1.0, 1.0).asin().to_degrees();
                e >= min_elevation_deg && e <= max_elevation_deg
            }
        }
    }

    /// One scan from `origin` with the robot heading `yaw`: every ray hitting the terrain within
    /// range gives a noisy coloured point (`colors`: one colour per world cell, row-major).
    /// `seed` and `scan_index` key the noise streams. The cloud's `sensor` index is 0; the
    /// [`crate::Simulator`] sets it to the sensor's place in the profile.
    ///
    /// An omnidirectional sensor casts each azimuth column at once
    /// ([`Heightfield::cast_column`]); the cloud is the same as when every ray is cast on its
    /// own ([`Self::scan_ray_by_ray`]).
    #[allow(clippy::too_many_arguments)]
    pub fn scan(
        &self,
        hf: &Heightfield,
        colors: &[Rgb8],
        origin: Point3,
        yaw: f64,
        noise: &ScanNoise,
        stamp: f64,
        seed: u64,
        scan_index: u64,
    ) -> PointCloud {
        let ctx = Scan::new(hf, colors, origin, yaw, self.spec.range, noise);
        let points = match self.spec.kind {
            SensorKind::Omni { columns, rows, .. } => {
                self.points_by_column(&ctx, columns as usize, rows as usize, seed, scan_index)
            }
            SensorKind::RgbD { .. } => self.points_by_ray(&ctx, seed, scan_index),
        };
        ctx.cloud(stamp, points)
    }

    /// [`Self::scan`] casting every ray on its own ([`Heightfield::cast_unit`]): the reference
    /// of the column casting, for tests and benchmarks.
    #[doc(hidden)]
    #[allow(clippy::too_many_arguments)]
    pub fn scan_ray_by_ray(
        &self,
        hf: &Heightfield,
        colors: &[Rgb8],
        origin: Point3,
        yaw: f64,
        noise: &ScanNoise,
        stamp: f64,
        seed: u64,
        scan_index: u64,
    ) -> PointCloud {
        let ctx = Scan::new(hf, colors, origin, yaw, self.spec.range, noise);
        let points = self.points_by_ray(&ctx, seed, scan_index);
        ctx.cloud(stamp, points)
    }

    /// The points of a scan, each ray cast on its own, chunk by chunk.
    fn points_by_ray(&self, ctx: &Scan, seed: u64, scan_index: u64) -> Vec<ColoredPoint> {
        let chunks: Vec<Vec<ColoredPoint>> = self
            .dirs
            .par_chunks(RAYS_PER_CHUNK)
            .enumerate()
            .map(|(ci, dirs)| {
                let mut rng = stream(seed, &[key::SCAN, scan_index, ci as u64]);
                let mut out = Vec::with_capacity(dirs.len());
                for &b in dirs {
                    let u = ctx.world_dir(b);
                    if let Some(hit) = ctx.hf.cast_unit(ctx.origin, u, ctx.range) {
                        out.push(ctx.point(&mut rng, u, hit.range, hit.index));
                    }
                }
                out
            })
            .collect();
        concat(chunks)
    }

    /// The points of an omnidirectional scan of `columns × rows` rays (row-major): the hits of
    /// each azimuth column cast at once, then the noise drawn chunk by chunk in ray order, as
    /// [`Self::points_by_ray`] draws it.
    fn points_by_column(
        &self,
        ctx: &Scan,
        columns: usize,
        rows: usize,
        seed: u64,
        scan_index: u64,
    ) -> Vec<ColoredPoint> {
        // Range and cell index of each ray's hit, column-major.
        let mut hits: Vec<Option<(f64, usize)>> = vec![None; self.dirs.len()];
        hits.par_chunks_mut(rows).enumerate().for_each_init(
            || (Vec::with_capacity(rows), Vec::with_capacity(rows)),
            |(dirs, column), (c, out)| {
                dirs.clear();
                dirs.extend((0..rows).map(|r| ctx.world_dir(self.dirs[r * columns + c])));
                ctx.hf.cast_column(ctx.origin, dirs, ctx.range, column);
                for (o, hit) in out.iter_mut().zip(column.iter()) {
                    *o = hit.map(|h| (h.range, h.index));
                }
            },
        );
        let chunks: Vec<Vec<ColoredPoint>> = (0..self.dirs.len().div_ceil(RAYS_PER_CHUNK))
            .into_par_iter()
            .map(|ci| {
                let mut rng = stream(seed, &[key::SCAN, scan_index, ci as u64]);
                let rays = ci * RAYS_PER_CHUNK..((ci + 1) * RAYS_PER_CHUNK).min(self.dirs.len());
                let mut out = Vec::with_capacity(rays.len());
                for i in rays {
                    if let Some((range, index)) = hits[(i % columns) * rows + i / columns] {
                        out.push(ctx.point(&mut rng, ctx.world_dir(self.dirs[i]), range, index));
                    }
                }
                out
            })
            .collect();
        concat(chunks)
    }
}

/// What every ray of one scan shares.
struct Scan<'a> {
    hf: &'a Heightfield,
    colors: &'a [Rgb8],
    origin: Point3,
    /// Sine and cosine of the robot's heading.
    sy: f64,
    cy: f64,
    range: f64,
    noise: &'a ScanNoise,
}

impl<'a> Scan<'a> {
    fn new(
        hf: &'a Heightfield,
        colors: &'a [Rgb8],
        origin: Point3,
        yaw: f64,
        range: f64,
        noise: &'a ScanNoise,
    ) -> Self {
        let (sy, cy) = yaw.sin_cos();
        Self {
            hf,
            colors,
            origin,
            sy,
            cy,
            range,
            noise,
        }
    }

    /// The world-frame direction of body-frame ray `b`.
    #[inline]
    fn world_dir(&self, b: [f64; 3]) -> [f64; 3] {
        let (sy, cy) = (self.sy, self.cy);
        [b[0] * cy - b[1] * sy, b[0] * sy + b[1] * cy, b[2]]
    }

    /// The noisy point of a hit at true range `r` in cell `index` along `u`.
    #[inline]
    fn point(&self, rng: &mut ChaCha8Rng, u: [f64; 3], r: f64, index: usize) -> ColoredPoint {
        let color = self.colors.get(index).copied().unwrap_or_default();
        noisy_point(rng, self.noise, self.origin, u, r, color)
    }

    fn cloud(&self, stamp: f64, points: Vec<ColoredPoint>) -> PointCloud {
        PointCloud {
            stamp,
            origin: self.origin,
            points,
            ..PointCloud::default()
        }
    }
}

/// The points of all chunks, in chunk order.
fn concat(chunks: Vec<Vec<ColoredPoint>>) -> Vec<ColoredPoint> {
    let mut points = Vec::with_capacity(chunks.iter().map(Vec::len).sum());
    for c in chunks {
        points.extend_from_slice(&c);
    }
    points
}

/// The rays of a pinhole camera, body frame: one through the centre of each pixel of a
/// `width × height` image (row 0 at the top, column 0 at the left) spanning `hfov × vfov`,
/// the optical axis tilted down by `tilt_deg`, then turned by the mounting `yaw` (radians).
fn pinhole_rays(
    hfov_deg: f64,
    vfov_deg: f64,
    (width, height): (u32, u32),
    tilt_deg: f64,
    yaw: f64,
) -> Vec<[f64; 3]> {
    let (sy, cy) = yaw.sin_cos();
    let (th, tv) = (
        (hfov_deg.to_radians() / 2.0).tan(),
        (vfov_deg.to_radians() / 2.0).tan(),
    );
    let (st, ct) = tilt_deg.to_radians().sin_cos();
    let mut dirs = Vec::with_capacity(width as usize * height as usize);
    for r in 0..height {
        let v = (1.0 - 2.0 * (r as f64 + 0.5) / height as f64) * tv;
        for c in 0..width {
            let h = (1.0 - 2.0 * (c as f64 + 0.5) / width as f64) * th;
            // Camera frame: x forward, y left, z up; then tilt down, then yaw.
            let n = (1.0 + h * h + v * v).sqrt();
            let (x, y, z) = (1.0 / n, h / n, v / n);
            let (x, z) = (x * ct + z * st, -x * st + z * ct);
            dirs.push([x * cy - y * sy, x * sy + y * cy, z]);
        }
    }
    dirs
}

/// The rays of an omnidirectional sensor, body frame: `columns` azimuths over 360° from the
/// mounting `yaw` (radians) times `rows` elevations spread evenly over `elevation_deg` (one row:
/// the middle).
fn omni_rays(elevation_deg: (f64, f64), columns: u32, rows: u32, yaw: f64) -> Vec<[f64; 3]> {
    let (min_deg, max_deg) = elevation_deg;
    let mut dirs = Vec::with_capacity(columns as usize * rows as usize);
    for r in 0..rows {
        let f = if rows > 1 {
            r as f64 / (rows - 1) as f64
        } else {
            0.5
        };
        let e = (min_deg + f * (max_deg - min_deg)).to_radians();
        let (se, ce) = e.sin_cos();
        for c in 0..columns {
            let a = yaw + std::f64::consts::TAU * c as f64 / columns as f64;
            let (sa, ca) = a.sin_cos();
            dirs.push([ce * ca, ce * sa, se]);
        }
    }
    dirs
}

/// The noisy return of a hit at true range `r` along unit direction `u`.
#[inline]
fn noisy_point(
    rng: &mut ChaCha8Rng,
    noise: &ScanNoise,
    origin: Point3,
    u: [f64; 3],
    r: f64,
    color: Rgb8,
) -> ColoredPoint {
    let e: f64 = rng.sample(StandardNormal);
    let rn = r + noise.depth_std(r) * e;
    let mut rgb = color.0;
    for ch in &mut rgb {
        let e: f64 = rng.sample(StandardNormal);
        // Round half up, clamped to 0–255 by the saturating cast (NaN → 0), without a libm call
        // per channel. It equals round().clamp() except where adding 0.5 itself rounds (values
        // within an ulp below a half), which only moves a noise sample by one level.
        *ch = (*ch as f64 + noise.color_sigma * e + 0.5) as u8;
    }
    ColoredPoint {
        x: (origin.x + u[0] * rn) as f32,
        y: (origin.y + u[1] * rn) as f32,
        z: (origin.z + u[2] * rn) as f32,
        rgb,
    }
}
