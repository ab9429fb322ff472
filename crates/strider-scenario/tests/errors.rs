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
        m.ends_with(
            "scenario.toml: world.resolution = -0.05: must be a finite number in [0.001, 100] m"
        ),
        "{m}"
    );
    let (_, m) = edited_err("res0", "resolution = 0.05", "resolution = 0.0");
    assert!(m.contains("world.resolution = 0: must be"), "{m}");
    let (_, m) = edited_err("origin", "origin = [0.0, 0.0]", "origin = [0.03, 0.0]");
    assert!(
        m.contains("[world] origin [0.03, 0] must be a multiple of the resolution"),
        "{m}"
    );
    // A lattice-aligned origin shifts the cells.
    let dir = fixture("origin-ok");
    edit_toml(&dir, "origin = [0.0, 0.0]", "origin = [-1.0, 0.5]");
    edit_toml(&dir, "x = 0.6", "x = -0.4");
    edit_toml(
        &dir,
        "min = { x = 0.25, y = 0.25 }",
        "min = { x = -0.75, y = 0.75 }",
    );
    edit_toml(
        &dir,
        "max = { x = 5.75, y = 4.75 }",
        "max = { x = 4.75, y = 5.25 }",
    );
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
    let (_, m) = edited_err(
        "bounds",
        "max = { x = 5.75, y = 4.75 }",
        "max = { x = 1e300, y = 4.75 }",
    );
    assert!(
        m.contains(
            "[bounds] min (0.25, 0.25) … max (1e300, 4.75) reach beyond the world [0, 6] × [0, 5] m"
        ),
        "{m}"
    );
    let (_, m) = edited_err("tour", "{ x = 5.4, y = 4.4 }", "{ x = 5.4, y = -4.4 }");
    assert!(
        m.contains("[[tours]] 'corners' waypoint 3: (5.4, -4.4) lies outside the world"),
        "{m}"
    );
}

#[test]
fn map_parameters_are_checked_with_key_value_and_range() {
    for (tag, from, to, expected) in [
        (
            "sigma",
            "r_robot = 0.25",
            "r_robot = 0.25\nsigma_d = nan",
            "map.sigma_d = NaN: must be a finite number in [1e-6, 10] m",
        ),
        (
            "cell",
            "cell_size = 0.05",
            "cell_size = -0.1",
            "map.cell_size = -0.1: must be a finite number in [0.01, 10] m",
        ),
        (
            "cell-tiny",
            "cell_size = 0.05",
            "cell_size = 0.001",
            "map.cell_size = 0.001: must be a finite number in [0.01, 10] m",
        ),
        (
            "cell-finer",
            "cell_size = 0.05",
            "cell_size = 0.02",
            "map.cell_size = 0.02: must be in [0.05, 1.25] m: not finer than the world's resolution",
        ),
        (
            "cell-coarse",
            "cell_size = 0.05",
            "cell_size = 2.0",
            "map.cell_size = 2: must be in [0.05, 1.25] m: not finer than the world's resolution, and at least 4 cells across the world's shorter side (5 m)",
        ),
        (
            "tile",
            "r_robot = 0.25",
            "r_robot = 0.25\ntile_size = 100000",
            "map.tile_size = 100000: must be an integer in [1, 1024] cells",
        ),
        (
            "r-nan",
            "r_robot = 0.25",
            "r_robot = nan",
            "map.r_robot = NaN: must be a finite number in [0, 10]",
        ),
        (
            "r-neg",
            "r_robot = 0.25",
            "r_robot = -0.25",
            "map.r_robot = -0.25: must be",
        ),
        (
            "r-huge",
            "r_robot = 0.25",
            "r_robot = 1e9",
            "map.r_robot = 1e9: must be a finite number in [0, 10] m (at most 200 cells of map.cell_size = 0.05 m)",
        ),
        (
            "point-range",
            "r_robot = 0.25",
            "r_robot = 0.25\nmax_point_range = 0.0",
            "map.max_point_range = 0: must be a finite number in [2.5, 50]",
        ),
    ] {
        let (e, m) = edited_err(tag, from, to);
        assert!(matches!(e, ScenarioError::Param { .. }), "{tag}: {m}");
        assert!(m.contains(expected), "{tag}: {m}");
        assert!(m.contains("scenario.toml: "), "{tag}: {m}");
    }
}

#[test]
fn simulator_parameters_are_bounded() {
    for (tag, to, expected) in [
        (
            "dt",
            "dt = 1e-9",
            "sim.dt = 1e-9: must be a finite number in [0.001, 1] s",
        ),
        (
            "pose-rate",
            "pose_rate_hz = 1e9",
            "sim.pose_rate_hz = 1e9: must be a finite number in [0.1, 1000] Hz",
        ),
        (
            "proprio-rate",
            "proprio_rate_hz = 0.0",
            "sim.proprio_rate_hz = 0: must be",
        ),
        (
            "noise",
            "speed_noise = -1.0",
            "sim.speed_noise = -1: must be",
        ),
    ] {
        let (_, m) = edited_err(tag, "speed_noise = 0.05", to);
        assert!(m.contains(expected), "{tag}: {m}");
    }
    let (_, m) = edited_err("time", "time_limit_s = 3600.0", "time_limit_s = 1e300");
    assert!(
        m.contains("time_limit_s = 1e300: must be a finite number in (0, 1e6] s"),
        "{m}"
    );
}

#[test]
fn robot_and_sensor_parameters_are_bounded() {
    let sensor = |extra: &str| {
        format!(
            "max_step_m = 0.12\nsensors = [{{ kind = \"rgb-d\", hfov_deg = 87.0, vfov_deg = 58.0, width_px = 160, height_px = 120, range = 2.5, height = 0.3{extra} }}]"
        )
    };
    for (tag, to, expected) in [
        (
            "pixels",
            sensor(", width_px = 100000, height_px = 10000").replace(
                "width_px = 160, height_px = 120, ",
                "",
            ),
            "robot.sensors[0].width_px × height_px = 100000 × 10000 = 1000000000 rays: must be at most 1048576 rays per scan",
        ),
        (
            "range",
            sensor("").replace("range = 2.5", "range = 1e12"),
            "robot.sensors[0].range = 1e12: must be a finite number in (0, 1000] m",
        ),
        (
            "below",
            sensor("").replace("height = 0.3", "height = -0.3"),
            "robot.sensors[0].height = -0.3: must be a finite number in (0, 100] m",
        ),
        (
            "rate",
            sensor(", rate_hz = 1e9"),
            "robot.sensors[0].rate_hz = 1e9: must be a finite number in [0.1, 100] Hz",
        ),
        (
            "fov",
            sensor("").replace("hfov_deg = 87.0", "hfov_deg = 180.0"),
            "robot.sensors[0].hfov_deg = 180: must be a finite number in (0, 179] °",
        ),
        (
            "footprint",
            "max_step_m = 0.12\nfootprint_radius = 1e9".to_string(),
            "robot.footprint_radius = 1e9: must be a finite number in [0, 100] m",
        ),
        (
            "footprint-cells",
            "max_step_m = 0.12\nfootprint_radius = 20.0".to_string(),
            "robot.footprint_radius = 20: must be a finite number in [0, 10] m (at most 200 cells of world.resolution = 0.05 m)",
        ),
        (
            "speed",
            "max_step_m = 0.12\ngaits = [{ name = \"fast\", max_speed = 1e300 }, { name = \"tall\", max_speed = 0.1 }]"
                .to_string(),
            "robot.gaits[0].max_speed = 1e300: must be a finite number in (0, 10] m/s",
        ),
    ] {
        let (e, m) = edited_err(tag, "max_step_m = 0.12", &to);
        assert!(matches!(e, ScenarioError::Param { .. }), "{tag}: {m}");
        assert!(m.contains(expected), "{tag}: {m}");
    }
}

#[test]
fn a_robot_without_sensors_loads() {
    let dir = fixture("nosensor");
    edit_toml(&dir, "max_step_m = 0.12", "max_step_m = 0.12\nsensors = []");
    assert!(Scenario::load(&dir).unwrap().robot.sensors.is_empty());
}

#[test]
fn start_yaw_and_elevation_scale_say_what_is_wrong() {
    let (_, m) = edited_err("yaw", "yaw = 0.0", "yaw = nan");
    assert!(
        m.ends_with("scenario.toml: start.yaw = NaN: must be a finite angle in radians"),
        "{m}"
    );
    let (_, m) = edited_err("scale", "scale = 0.0005", "scale = 1e300");
    assert!(
        m.ends_with(
            "scenario.toml: world.elevation.scale = 1e300: must be a finite number in [1e-6, 1] m"
        ),
        "{m}"
    );
    let (_, m) = edited_err("offset", "offset = -1.0", "offset = -inf");
    assert!(m.contains("world.elevation.offset = -inf: must be"), "{m}");
}

#[test]
fn start_in_a_wall_or_against_it_is_refused() {
    // The fixture's top row (y ∈ [4.95, 5.0)) is a 0.3 m wall; the row below it borders it.
    let (_, m) = edited_err("wall", "x = 0.6\ny = 0.6", "x = 0.61\ny = 4.97");
    assert!(
        m.contains("[start] (0.61, 4.97) is in an obstacle: its cell (12, 99) has a step of 0.3")
            && m.contains("more than map.rho_obstacle = 0.25 m"),
        "{m}"
    );
    let (_, m) = edited_err("near-wall", "x = 0.6\ny = 0.6", "x = 0.61\ny = 4.8");
    assert!(
        m.contains(
            "[start] (0.61, 4.8) is within map.r_robot = 0.25 m of the obstacle cell (12, 98)"
        ),
        "{m}"
    );
    // One footprint away from the wall is open ground.
    let dir = fixture("clear");
    edit_toml(&dir, "y = 0.6\nyaw", "y = 4.6\nyaw");
    Scenario::load(&dir).unwrap();
}

/// A PNG whose header claims `w × h` pixels, with a tiny (invalid) image data chunk.
fn huge_png_header(w: u32, h: u32) -> Vec<u8> {
    fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
        out.extend((data.len() as u32).to_be_bytes());
        let start = out.len();
        out.extend(kind);
        out.extend(data);
        let crc = crc32(&out[start..]);
        out.extend(crc.to_be_bytes());
    }
    fn crc32(bytes: &[u8]) -> u32 {
        let mut c = !0u32;
        for &b in bytes {
            c ^= b as u32;
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    0xEDB8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    let mut ihdr = Vec::new();
    ihdr.extend(w.to_be_bytes());
    ihdr.extend(h.to_be_bytes());
    ihdr.extend([8, 2, 0, 0, 0]); // 8-bit RGB
    chunk(&mut out, b"IHDR", &ihdr);
    chunk(&mut out, b"IDAT", &[0x78, 0x9C, 0x03, 0x00]);
    chunk(&mut out, b"IEND", &[]);
    out
}

#[test]
fn a_png_claiming_a_huge_size_is_refused_before_decoding() {
    let dir = fixture("huge");
    let png = huge_png_header(1_000_000, 1_000_000);
    assert!(png.len() < 80, "{}", png.len());
    std::fs::write(dir.join("color.png"), &png).unwrap();
    let (e, m) = load_err(&dir);
    assert!(matches!(e, ScenarioError::Param { .. }), "{m}");
    assert!(
        m.contains("color.png: world size = 1000000 × 1000000 = 1000000000000 cells: must be at most 16777216 cells"),
        "{m}"
    );
    // Just inside the limit: refused only when the (missing) data is decoded.
    std::fs::write(dir.join("color.png"), huge_png_header(4096, 4096)).unwrap();
    let (e, m) = load_err(&dir);
    assert!(matches!(e, ScenarioError::Png { .. }), "{m}");
}

#[test]
fn scenarios_load_from_memory() {
    use std::collections::BTreeMap;
    let dir = fixture("memory");
    let layers: BTreeMap<String, Vec<u8>> = ["color.png", "elevation.png", "terrain.png"]
        .iter()
        .map(|n| (n.to_string(), std::fs::read(dir.join(n)).unwrap()))
        .collect();
    let file = Path::new("mem.toml");
    let s = Scenario::from_toml_str(EXAMPLE, file, &layers).unwrap();
    assert_eq!(s, Scenario::load(&dir).unwrap());
    let mut missing = layers.clone();
    missing.remove("terrain.png");
    let e = Scenario::from_toml_str(EXAMPLE, file, &missing).unwrap_err();
    assert_eq!(
        e.to_string(),
        "terrain.png: file not found (terrain layer named in [world] terrain)"
    );
}
