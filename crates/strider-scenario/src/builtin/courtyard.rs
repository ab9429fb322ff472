//! What the two courtyards (Prágr22 §5.1) share: gray and red pavement that both gaits cross at
//! full speed, green and brown turf on which the fast gait gets stuck and the tall gait reaches
//! 0.8 of its speed, and the strategy parameters of Prágr22 Table 3.

use strider_core::Rgb8;

use super::strategy;
use super::terrains::{Look, TerrainTable, speed, stuck};

/// Terrain indices: gray pavement.
pub(super) const GRAY: u8 = 0;
/// Red pavement.
pub(super) const RED: u8 = 1;
/// Green turf.
pub(super) const GREEN_TURF: u8 = 2;
/// Brown turf (brown-green in the large courtyard).
pub(super) const BROWN_TURF: u8 = 3;

/// Turf colours.
pub(super) const GREEN: Rgb8 = Rgb8::new(50, 150, 50);
pub(super) const BROWN: Rgb8 = Rgb8::new(130, 90, 50);

/// The strategies of Prágr22, which Table 3 parametrises.
pub(super) const STRATEGIES: [&str; 3] = ["gtsp", "greedy", "spatial-only"];

/// Pavement and turf: the green turf's elevation texture is `green_texture`; `brown` names and
/// draws the second turf.
pub(super) fn terrains(green_texture: f32, brown: (&str, Look)) -> TerrainTable {
    let pavement = [("fast", speed(1.0)), ("tall", speed(1.0))];
    let turf = [("fast", stuck(0.02)), ("tall", speed(0.8))];
    TerrainTable::new()
        .add(
            GRAY,
            "gray pavement",
            &pavement,
            Look::new(Rgb8::new(128, 128, 128), 7.0, 0.001),
        )
        .add(
            RED,
            "red pavement",
            &pavement,
            Look::new(Rgb8::new(190, 40, 40), 7.0, 0.001),
        )
        .add(
            GREEN_TURF,
            "green turf",
            &turf,
            Look::new(GREEN, 9.0, green_texture),
        )
        .add(BROWN_TURF, brown.0, &turf, brown.1)
}

/// Prágr22 Table 3 values for the Prágr22 strategies; `large` selects the right column. (Table 3's
/// v_max is the robot profile's fastest gait.)
pub(super) fn table3(large: bool) -> toml::Table {
    let pick = |small: f64, big: f64| if large { big } else { small };
    strategy::params(
        &[
            ("delta_t", pick(5.0, 1.0)),
            ("c_loss", pick(10.0, 7.5)),
            ("c_high", 20.0),
            ("c_max", 20.0),
            ("sigma_sense", 0.10),
            ("sigma_0_sq", 1.0),
            ("sigma_s", 1.0),
            ("sigma_eps", 0.5),
            ("lengthscale", 0.4),
            ("d_s", 0.44),
            ("igng_eps_winner", 1e-3),
            ("igng_eps_neighbour", 1e-5),
            ("dt_sample", pick(30.0, 12.0)),
            ("dt_fallback", pick(30.0, 3.0)),
        ],
        &[
            ("n_min", 25),
            ("n_erode_steps", 2),
            ("m_t", 10),
            ("n_dilate_steps", 3),
            ("n_dilate_size", 2),
            ("igng_age_mature", 100),
            ("igng_age_max", 50),
            ("igng_batch", 5000),
        ],
    )
}
