//! The figures of Prágr22 Fig. 5 and Fig. 7 over the map's known area: map colour, dominant
//! colour prototype, merged planning cost and selected gait (Eq. 13), per gait the learned cell
//! costs, the classes (dilated, Alg. 10), the planning cost and the raw GP prediction with its
//! variance, the exploration path, and the tour paths of each navigation mode.

use std::collections::HashMap;
use std::path::Path;

use anyhow::Result;
use strider_core::color::COLOR_PROTOTYPES;
use strider_core::{Cell, CellRect, Point2, Rgb8};
use strider_explore::evaluate::TourResult;
use strider_explore::planner::{CostMode, PlanningView};
use strider_explore::{Mission, TourExplorer};
use strider_learn::cost_model::GaitCostModel;

use crate::render::{Canvas, palette, rgb_canvas, scalar_canvas, viridis};
use crate::report::{Extent, Key, MapFigure};

/// The colour of the exploration path.
const PATH_COLOUR: [u8; 3] = [255, 0, 255];

/// The inverse-velocity cost (Prágr22 Eq. 19–20): 1 is ideal terrain at the gait's full speed.
const COST: &str = "cost";

/// What every figure of one mission shares: the known area, cell size, pixel scale and cost
/// range.
struct Frame<'a> {
    mission: &'a Mission<TourExplorer>,
    rect: CellRect,
    d: f64,
    scale: u32,
    c_max: f32,
    colors: Vec<Option<Rgb8>>,
    out: &'a Path,
    gaits: Vec<String>,
}

impl Frame<'_> {
    /// Saves a scalar layer of `quantity` in the cost range (or its own range) and describes it.
    fn scalar(
        &self,
        values: &[f32],
        cost_range: bool,
        file: &str,
        (title, quantity, caption): (&str, &str, &str),
    ) -> Result<MapFigure> {
        let range = cost_range.then_some((1.0, self.c_max));
        let (canvas, (lo, hi)) = scalar_canvas(self.rect, self.d, self.scale, values, range);
        canvas.save(&self.out.join(file))?;
        let key = Key::ColourBar {
            quantity: quantity.to_string(),
            unit: String::new(),
            min: lo as f64,
            max: hi as f64,
            colormap: viridis,
        };
        Ok(self.figure(file, title, caption, key))
    }

    /// Describes a figure written to `file` over the frame's area.
    fn figure(&self, file: &str, title: &str, caption: &str, key: Key) -> MapFigure {
        MapFigure {
            src: file.to_string(),
            title: title.to_string(),
            caption: caption.to_string(),
            extent: Extent::of_cells(self.rect, self.d),
            key,
        }
    }

    /// The legend of the gaits, in the palette's order.
    fn gait_legend(&self) -> Vec<(String, [u8; 3])> {
        self.gaits
            .iter()
            .enumerate()
            .map(|(k, g)| (format!("gait {g}"), palette(k)))
            .collect()
    }

    /// A canvas of the map's colours.
    fn colour_canvas(&self) -> Canvas {
        rgb_canvas(self.rect, self.d, self.scale, &self.colors)
    }
}

/// Writes the figures of `mission` and its driven `tours` into `out` and returns what the report
/// needs to show them (nothing before anything is mapped).
pub fn write_figures(
    mission: &Mission<TourExplorer>,
    tours: &[(String, Vec<TourResult>)],
    out: &Path,
) -> Result<Vec<MapFigure>> {
    let map = mission.body().map();
    let Some(rect) = map.known_bounds() else {
        return Ok(Vec::new());
    };
    let f = Frame {
        mission,
        rect,
        d: map.cell_size(),
        scale: Canvas::auto_scale(rect, 900),
        c_max: mission.strategy().params().cost_model.c_max as f32,
        colors: map.color_raster(rect),
        out,
        gaits: mission
            .strategy()
            .params()
            .gaits
            .iter()
            .map(|g| g.name.clone())
            .collect(),
    };
    f.colour_canvas().save(&out.join("color.png"))?;
    let mut figures = vec![f.figure(
        "color.png",
        "Map colour",
        "The mean colour of the points that fell in each cell.",
        Key::TrueColour {
            overlays: Vec::new(),
        },
    )];
    figures.push(dominant_colour(&f)?);
    figures.extend(planning_view(&f)?);
    for (gi, m) in mission.strategy().models().iter().enumerate() {
        figures.extend(gait_figures(&f, &f.gaits[gi], m)?);
    }
    figures.extend(paths(&f, tours)?);
    Ok(figures)
}

/// Fig. 5E: the dominant colour prototype of each cell's descriptor ta(ν).
fn dominant_colour(f: &Frame) -> Result<MapFigure> {
    let desc = f.mission.strategy().descriptors();
    let dominant: Vec<_> = f
        .rect
        .cells()
        .map(|c| {
            desc.get(c).and_then(|h| {
                h.iter()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(b.1))
                    .map(|(k, _)| COLOR_PROTOTYPES[k].1)
            })
        })
        .collect();
    rgb_canvas(f.rect, f.d, f.scale, &dominant).save(&f.out.join("dominant_colour.png"))?;
    let legend = COLOR_PROTOTYPES
        .iter()
        .map(|(name, c)| (name.to_string(), c.0))
        .collect();
    Ok(f.figure(
        "dominant_colour.png",
        "Dominant colour prototype",
        "The colour prototype with the largest share of each cell's 9-bin descriptor ta(ν) \
         (Fig. 5E).",
        Key::Legend(legend),
    ))
}

/// Fig. 5C–D: the merged planning cost and the cheapest gait per cell.
fn planning_view(f: &Frame) -> Result<Vec<MapFigure>> {
    let (map, ex) = (f.mission.body().map(), f.mission.strategy());
    let Some(view) = PlanningView::build(
        map,
        ex.models(),
        CostMode::Learned,
        ex.params().c_loss,
        ex.params().bounds.as_ref(),
    ) else {
        return Ok(Vec::new());
    };
    // The view covers the known area grown by the footprint; crop it to the known area.
    let vr = view.rect();
    let crop = |k: usize| vr.index(f.rect.cell(k));
    let merged: Vec<f32> = (0..f.rect.len())
        .map(|k| crop(k).map_or(f32::NAN, |i| view.grid.costs()[i]))
        .collect();
    let merged = f.scalar(
        &merged,
        true,
        "merged_cost.png",
        (
            "Planning cost",
            COST,
            "The minimum cost over gaits after the distance transform (Fig. 5C).",
        ),
    )?;
    let mut g = Canvas::new(f.rect, f.d, f.scale);
    let obs = map.observed_raster(f.rect);
    g.fill(|k| {
        obs[k]
            .then(|| crop(k).and_then(|i| view.best_gait[i]))
            .flatten()
            .map(|x| palette(x as usize))
    });
    g.save(&f.out.join("gait.png"))?;
    let gait = f.figure(
        "gait.png",
        "Cheapest gait",
        "The gait with the lowest planning cost in each cell (Fig. 5D).",
        Key::Legend(f.gait_legend()),
    );
    Ok(vec![merged, gait])
}

/// Fig. 5F–K for one gait: measured costs, classes, planning costs, raw prediction and its
/// variance.
fn gait_figures(f: &Frame, name: &str, m: &GaitCostModel) -> Result<Vec<MapFigure>> {
    let costs: Vec<f32> = f
        .rect
        .cells()
        .map(|c| m.cell_cost(c).map_or(f32::NAN, |k| k.cost as f32))
        .collect();
    let measured = f.scalar(
        &costs,
        true,
        &format!("measured_cost_{name}.png"),
        (
            &format!("Measured cost, gait {name}"),
            COST,
            "The fused measured costs (tanh-bounded) where the robot walked (Fig. 5F).",
        ),
    )?;
    let (mu, var) = prediction(f, m);
    let predicted = f.scalar(
        &mu,
        true,
        &format!("prediction_{name}.png"),
        (
            &format!("GP prediction, gait {name}"),
            COST,
            "The raw GP cost prediction at the described cells (Fig. 5G).",
        ),
    )?;
    let variance = f.scalar(
        &var,
        false,
        &format!("variance_{name}.png"),
        (
            &format!("GP variance, gait {name}"),
            "cost variance",
            "The latent variance of the GP prediction, on its own range (Fig. 5H).",
        ),
    )?;
    let classes = class_figure(f, name, m)?;
    let planning = f.scalar(
        &m.planning_costs(f.rect),
        true,
        &format!("planning_cost_{name}.png"),
        (
            &format!("Planning cost, gait {name}"),
            COST,
            "The class costs used in planning (Fig. 5K).",
        ),
    )?;
    Ok(vec![measured, predicted, variance, classes, planning])
}

/// Fig. 5I: the IGNG terrain classes after erosion and dilation, one colour per class.
fn class_figure(f: &Frame, name: &str, m: &GaitCostModel) -> Result<MapFigure> {
    let mut cl = Canvas::new(f.rect, f.d, f.scale);
    let cells: Vec<_> = f.rect.cells().map(|c| m.planning_class(c)).collect();
    cl.fill(|k| cells[k].map(|t| palette(t.0 as usize)));
    let file = format!("classes_{name}.png");
    cl.save(&f.out.join(&file))?;
    let mut ids: Vec<usize> = cells.iter().flatten().map(|t| t.0 as usize).collect();
    ids.sort_unstable();
    ids.dedup();
    let legend = ids
        .into_iter()
        .map(|k| (format!("class {k}"), palette(k)))
        .collect();
    Ok(f.figure(
        &file,
        &format!("Terrain classes, gait {name}"),
        "The IGNG terrain classes after erosion and dilation (Fig. 5I); the model's class table \
         above gives each class's cost.",
        Key::Legend(legend),
    ))
}

/// Fig. 5G–H: the raw GP prediction and its (latent) variance at the described cells: every
/// cell when there are few, else on a lattice of about 16384 cells with each lattice cell's
/// value shown over its block (a prediction costs O(n²), Prágr22 fn. 2).
fn prediction(f: &Frame, m: &GaitCostModel) -> (Vec<f32>, Vec<f32>) {
    let (rect, desc) = (f.rect, f.mission.strategy().descriptors());
    let stride = ((rect.len() as f64 / 16384.0).sqrt().ceil() as i32).max(1);
    let anchor = |c: Cell| {
        Cell::new(
            c.i - (c.i - rect.min.i).rem_euclid(stride),
            c.j - (c.j - rect.min.j).rem_euclid(stride),
        )
    };
    let lattice: Vec<Cell> = rect
        .cells()
        .filter(|&c| anchor(c) == c && desc.get(c).is_some())
        .collect();
    let xs: Vec<f64> = lattice
        .iter()
        .flat_map(|&c| desc.get(c).unwrap_or(&[]).iter().copied())
        .collect();
    let at: HashMap<Cell, (f64, f64)> = lattice.iter().copied().zip(m.predict_many(&xs)).collect();
    rect.cells()
        .map(|c| match (desc.get(c), at.get(&anchor(c))) {
            (Some(_), Some(&(mu, var))) => (mu as f32, var as f32),
            _ => (f32::NAN, f32::NAN),
        })
        .unzip()
}

/// Fig. 7: the exploration path, and every tour in every navigation mode coloured by gait.
fn paths(f: &Frame, tours: &[(String, Vec<TourResult>)]) -> Result<Vec<MapFigure>> {
    let mut path = f.colour_canvas();
    let pts: Vec<Point2> = f
        .mission
        .record()
        .trajectory
        .iter()
        .map(|s| Point2::new(s.x, s.y))
        .collect();
    path.polyline(&pts, PATH_COLOUR, 2);
    path.save(&f.out.join("exploration_path.png"))?;
    let mut figures = vec![f.figure(
        "exploration_path.png",
        "Exploration path",
        "The path the robot drove while it explored (Fig. 7).",
        Key::TrueColour {
            overlays: vec![("exploration path".to_string(), PATH_COLOUR)],
        },
    )];
    for (name, modes) in tours {
        for r in modes {
            let mut c = f.colour_canvas();
            for w in r.trajectory.windows(2) {
                let col = palette(w[0].gait as usize);
                c.polyline(
                    &[Point2::new(w[0].x, w[0].y), Point2::new(w[1].x, w[1].y)],
                    col,
                    2,
                );
            }
            let file = format!("tour_{name}_{}.png", r.mode.name());
            c.save(&f.out.join(&file))?;
            figures.push(f.figure(
                &file,
                &format!("Tour {name}, {} navigation", r.mode.name()),
                &format!(
                    "{:.0} s{}; the path is coloured by the gait it was walked in.",
                    r.total_s,
                    if r.completed { "" } else { " (incomplete)" }
                ),
                Key::TrueColour {
                    overlays: f.gait_legend(),
                },
            ));
        }
    }
    Ok(figures)
}
