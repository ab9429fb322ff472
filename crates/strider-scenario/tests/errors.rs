//! The file format: the documented example loads, and each kind of bad input gives a precise
//! one-line error naming the file.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use strider_scenario::{Scenario, ScenarioError};

/// The example of the `format` module documentation.
const EXAMPLE: &str = r#"
name = "my-yard"
description = "A paved yard with a lawn."
world_seed = 0
time_limit_s = 3600.0

[world]
resolution = 0.05
origin = [0.0, 0.0]
color = "color.png"
elevation = { file = "elevation.png", scale = 0.0005, offset = -1.0 }
terrain = "terrain.png"

[[terrain]]
index = 0
name = "pavement"
gaits.fast = { speed_factor = 1.0 }
gaits.tall = { speed_factor = 1.0 }

[[terrain]]
index = 1
name = "turf"
vibration = 0.0
energy_per_m = 1.0
gaits.fast = { speed_factor = 0.02, stuck = true }
gaits.tall = { speed_factor = 0.8, roll_variance = 0.0, power_w = 0.0 }

[[terrain]]
index = 2
name = "curtain"
push_force_n = 0.8

[robot]
profile = "hexapod-small"
max_step_m = 0.12

[map]
cell_size = 0.05
r_robot = 0.25

[sim]
speed_noise = 0.05

[strategy]
c_loss = 10.0

[start]
x = 0.6
y = 0.6
yaw = 0.0

[bounds]
min = { x = 0.25, y = 0.25 }
max = { x = 5.75, y = 4.75 }

[[tours]]
name = "corners"
closed = true
waypoints = [{ x = 0.6, y = 0.6 }, { x = 5.4, y = 0.6 }, { x = 5.4, y = 4.4 }]
"#;

const W: u32 = 120;
const H: u32 = 100;

fn write_png(
    path: &Path,
    w: u32,
    h: u32,
    color: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
) {
    let mut enc = png::Encoder::new(BufWriter::new(File::create(path).unwrap()), w, h);
    enc.set_color(color);
    enc.set_depth(depth);
    if color == png::ColorType::Indexed {
        enc.set_palette(vec![0u8, 0, 0, 0, 255, 0, 255, 0, 255, 255, 255, 255]);
    }
    let mut wr = enc.write_header().unwrap();
    wr.write_image_data(data).unwrap();
    wr.finish().unwrap();
}

/// Terrain (image order): top half turf (1), bottom half pavement (0).
fn terrain_px(x: u32, y: u32) -> u8 {
    let _ = x;
    u8::from(y < H / 2)
}

/// A temporary directory, removed on drop.
struct TempDir(PathBuf);

impl std::ops::Deref for TempDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for TempDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A fresh directory holding the example scenario.
fn fixture(tag: &str) -> TempDir {
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "strider-scenario-errors-{tag}-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("scenario.toml"), EXAMPLE).unwrap();
    let mut rgb = Vec::new();
    let mut elev = Vec::new();
    let mut terr = Vec::new();
    for y in 0..H {
        for x in 0..W {
            let t = terrain_px(x, y);
            rgb.extend(if t == 1 {
                [50, 150, 50]
            } else {
                [128, 128, 128]
            });
            // 2000 → z = -1 + 0.0005 * 2000 = 0.0; a 0.3 m wall along the top row.
            let v: u16 = if y == 0 { 2600 } else { 2000 };
            elev.extend(v.to_be_bytes());
            terr.push(t);
        }
    }
    use png::{BitDepth::*, ColorType::*};
    write_png(&dir.join("color.png"), W, H, Rgb, Eight, &rgb);
    write_png(&dir.join("elevation.png"), W, H, Grayscale, Sixteen, &elev);
    write_png(&dir.join("terrain.png"), W, H, Grayscale, Eight, &terr);
    TempDir(dir)
}

fn edit_toml(dir: &Path, from: &str, to: &str) {
    let p = dir.join("scenario.toml");
    let t = std::fs::read_to_string(&p).unwrap();
    assert!(t.contains(from), "fixture lacks {from:?}");
    std::fs::write(&p, t.replacen(from, to, 1)).unwrap();
}

fn load_err(dir: &Path) -> (ScenarioError, String) {
    let e = Scenario::load(dir).expect_err("load should fail");
    let m = e.to_string();
    assert!(!m.contains('\n'), "multi-line message: {m}");
    (e, m)
}

/// The error of loading the example with its first `from` replaced by `to`.
fn edited_err(tag: &str, from: &str, to: &str) -> (ScenarioError, String) {
    let dir = fixture(tag);
    edit_toml(&dir, from, to);
    load_err(&dir)
}

#[test]
fn documented_example_loads() {
    let dir = fixture("ok");
    let s = Scenario::load(dir.join("scenario.toml")).unwrap();
    assert_eq!(s.name, "my-yard");
    assert_eq!((s.world.width(), s.world.height()), (120, 100));
    // Top image row = highest y: model row 0 (lowest y) is pavement, the top row is the wall.
    assert_eq!(s.world.terrain[0], 0);
    assert_eq!(s.world.terrain[99 * 120], 1);
    assert!((s.world.elevation[99 * 120] - 0.3).abs() < 1e-6);
    assert_eq!(s.world.elevation[0], 0.0);
    let p = s
        .world
        .index_at(strider_core::Point2::new(0.1, 4.99))
        .unwrap();
    assert_eq!(s.world.terrain[p], 1);
    // Profile with override.
    assert_eq!(s.robot.name, "hexapod-small");
    assert_eq!(s.robot.max_step_m, 0.12);
    assert_eq!(s.robot.gaits.len(), 2);
    assert_eq!(s.world.terrain_type(2).unwrap().push_force_n, Some(0.8));
    assert!(s.world.terrain_type(1).unwrap().gaits["fast"].stuck);
    assert_eq!(s.strategy["c_loss"].as_float(), Some(10.0));
    // Save → load of a loaded file round-trips too.
    let out = dir.join("copy");
    s.save(&out).unwrap();
    assert_eq!(Scenario::load(&out).unwrap(), s);
    // Indexed terrain PNGs are read by palette index.
    let mut packed = Vec::new();
    for y in 0..H {
        let mut row = vec![0u8; (W as usize).div_ceil(4)];
        for x in 0..W {
            row[x as usize / 4] |= terrain_px(x, y) << (6 - 2 * (x % 4));
        }
        packed.extend(row);
    }
    write_png(
        &dir.join("terrain.png"),
        W,
        H,
        png::ColorType::Indexed,
        png::BitDepth::Two,
        &packed,
    );
    let s2 = Scenario::load(&dir).unwrap();
    assert_eq!(s2.world.terrain, s.world.terrain);
}

#[test]
fn missing_layer_file() {
    let dir = fixture("missing");
    std::fs::remove_file(dir.join("elevation.png")).unwrap();
    let (e, m) = load_err(&dir);
    assert!(matches!(e, ScenarioError::MissingFile { .. }));
    assert!(m.contains("elevation.png: file not found"), "{m}");
    let (_, m) = load_err(&dir.join("nope"));
    assert!(m.contains("not found"), "{m}");
}

#[test]
fn wrong_png_depth() {
    let dir = fixture("depth");
    std::fs::copy(dir.join("color.png"), dir.join("elevation.png")).unwrap();
    let (e, m) = load_err(&dir);
    assert!(matches!(e, ScenarioError::PngFormat { .. }));
    assert!(
        m.ends_with("elevation.png: expected 16-bit grayscale, found 8-bit RGB"),
        "{m}"
    );
    let dir = fixture("depth2");
    std::fs::copy(dir.join("elevation.png"), dir.join("color.png")).unwrap();
    let (_, m) = load_err(&dir);
    assert!(
        m.ends_with("color.png: expected 8-bit RGB, found 16-bit grayscale"),
        "{m}"
    );
    std::fs::write(dir.join("color.png"), b"not a png").unwrap();
    let (e, m) = load_err(&dir);
    assert!(matches!(e, ScenarioError::Png { .. }), "{m}");
}

#[test]
fn size_mismatch() {
    let dir = fixture("size");
    write_png(
        &dir.join("terrain.png"),
        10,
        5,
        png::ColorType::Grayscale,
        png::BitDepth::Eight,
        &[0; 50],
    );
    let (e, m) = load_err(&dir);
    assert!(matches!(e, ScenarioError::SizeMismatch { .. }));
    assert!(
        m.contains("terrain.png: size 10×5 differs from") && m.contains("color.png (120×100)"),
        "{m}"
    );
}

#[test]
fn unknown_terrain_index() {
    let dir = fixture("index");
    let mut terr: Vec<u8> = (0..W * H).map(|k| terrain_px(k % W, k / W)).collect();
    terr[(7 * W + 3) as usize] = 9;
    terr[(8 * W + 3) as usize] = 9;
    write_png(
        &dir.join("terrain.png"),
        W,
        H,
        png::ColorType::Grayscale,
        png::BitDepth::Eight,
        &terr,
    );
    let (e, m) = load_err(&dir);
    assert!(
        matches!(
            e,
            ScenarioError::UnknownTerrainIndex {
                index: 9,
                x: 3,
                y: 7,
                count: 2,
                ..
            }
        ),
        "{m}"
    );
    assert!(
        m.contains("terrain.png: terrain index 9") && m.contains("column 3, row 7"),
        "{m}"
    );
}

#[test]
fn bad_resolution_and_origin() {
    let (_, m) = edited_err("res", "resolution = 0.05", "resolution = -0.05");
    assert!(
        m.contains("scenario.toml: [world] resolution must be a positive number"),
        "{m}"
    );
    let (_, m) = edited_err("res0", "resolution = 0.05", "resolution = 0.0");
    assert!(m.contains("resolution must be a positive"), "{m}");
    let (_, m) = edited_err("origin", "origin = [0.0, 0.0]", "origin = [0.03, 0.0]");
    assert!(
        m.contains("[world] origin [0.03, 0] must be a multiple of the resolution"),
        "{m}"
    );
    // A lattice-aligned origin shifts the cells.
    let dir = fixture("origin-ok");
    edit_toml(&dir, "origin = [0.0, 0.0]", "origin = [-1.0, 0.5]");
    edit_toml(&dir, "x = 0.6", "x = -0.4");
    edit_toml(&dir, "[[tours]]", "[[tours]]\n# moved");
    edit_toml(
        &dir,
        "waypoints = [{ x = 0.6, y = 0.6 }, { x = 5.4, y = 0.6 }, { x = 5.4, y = 4.4 }]",
        "waypoints = [{ x = 0.6, y = 0.6 }]",
    );
    let s = Scenario::load(&dir).unwrap();
    assert_eq!(s.world.rect.min, strider_core::Cell::new(-20, 10));
}

#[test]
fn malformed_toml_has_line_and_column() {
    let (e, m) = edited_err(
        "toml",
        "[sim]\nspeed_noise = 0.05",
        "[sim]\nspeed_noise = = 0.05",
    );
    let ScenarioError::Toml { line, column, .. } = e else {
        panic!("{m}")
    };
    let expected_line = EXAMPLE
        .lines()
        .position(|l| l.starts_with("speed_noise"))
        .unwrap()
        + 1;
    assert_eq!(line, expected_line, "{m}");
    assert!(column > 1, "{m}");
    assert!(
        m.contains(&format!("scenario.toml:{line}:{column}: ")),
        "{m}"
    );
    // Unknown keys and wrong types are TOML errors too.
    let (e, m) = edited_err(
        "toml2",
        "[sim]\nspeed_noise = 0.05",
        "[sim]\nspeed_nois = 0.05",
    );
    assert!(
        matches!(e, ScenarioError::Toml { .. }) && m.contains("speed_nois"),
        "{m}"
    );
}

#[test]
fn unknown_gait_and_profile() {
    let (_, m) = edited_err(
        "gait",
        "gaits.tall = { speed_factor = 0.8,",
        "gaits.trot = { speed_factor = 0.8,",
    );
    assert!(
        m.contains("[[terrain]] 'turf' (index 1): unknown gait 'trot'") && m.contains("fast, tall"),
        "{m}"
    );
    let (_, m) = edited_err(
        "profile",
        "profile = \"hexapod-small\"",
        "profile = \"hexapod-tiny\"",
    );
    assert!(
        m.contains("[robot] unknown profile 'hexapod-tiny'") && m.contains("hexapod-large"),
        "{m}"
    );
}

#[test]
fn start_and_tours_outside_the_world() {
    let (_, m) = edited_err("start", "x = 0.6", "x = 7.5");
    assert!(
        m.contains("[start] (7.5, 0.6) lies outside the world [0, 6] × [0, 5] m"),
        "{m}"
    );
    let (_, m) = edited_err("tour", "{ x = 5.4, y = 4.4 }", "{ x = 5.4, y = -4.4 }");
    assert!(
        m.contains("[[tours]] 'corners' waypoint 3: (5.4, -4.4) lies outside the world"),
        "{m}"
    );
}
