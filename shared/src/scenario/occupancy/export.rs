//! Any scenario written as a map_server map: the area and obstacles drawn
//! into a PGM image (free 254, occupied 0, outside the area unknown 205,
//! as map_saver writes them), the YAML file naming it, and the sidecar
//! with everything else, so that reading the map back keeps the targets,
//! starts and parameters. Curved and slanted edges come back as steps of
//! one pixel: a pixel is occupied when its centre is in an obstacle.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::image::MAX_IMAGE_PIXELS;
use super::sidecar_path;
use crate::agreement::shown;
use crate::geometry::{Point, Shape};
use crate::scenario::Scenario;

/// The default pixel side, in grid sides (the default cell side of reading).
pub const DEFAULT_RESOLUTION_SIDES: f64 = 0.1;

const FREE: u8 = 254;
const OCCUPIED: u8 = 0;
const UNKNOWN: u8 = 205;

/// The image: `width x height` pixels of side `res`, top row first, its
/// lower-left corner at `origin`.
struct Image {
    width: usize,
    height: usize,
    origin: Point,
    res: f64,
    pixels: Vec<u8>,
}

impl Image {
    /// Sets to `value` the pixels of row `yb` (from the bottom) whose
    /// centres lie between each pair of `crossings` (sorted x's).
    fn fill(&mut self, yb: usize, crossings: &[f64], value: u8) {
        let row = (self.height - 1 - yb) * self.width;
        for pair in crossings.chunks_exact(2) {
            let col = |x: f64| ((x - self.origin.x) / self.res - 0.5).ceil().clamp(0.0, self.width as f64) as usize;
            for p in &mut self.pixels[row + col(pair[0])..row + col(pair[1])] {
                *p = value;
            }
        }
    }

    /// The rows (from the bottom) whose centres may lie between `lo` and `hi`.
    fn rows(&self, lo: f64, hi: f64) -> std::ops::Range<usize> {
        let row = |y: f64| ((y - self.origin.y) / self.res - 0.5).ceil().clamp(0.0, self.height as f64) as usize;
        row(lo)..row(hi)
    }

    fn centre_y(&self, yb: usize) -> f64 {
        self.origin.y + (yb as f64 + 0.5) * self.res
    }
}

/// Where a horizontal line at `y` crosses the polygon's edges, sorted.
fn crossings(points: &[Point], y: f64) -> Vec<f64> {
    let n = points.len();
    let mut xs: Vec<f64> = (0..n)
        .filter_map(|k| {
            let (a, b) = (points[k], points[(k + 1) % n]);
            ((a.y <= y) != (b.y <= y)).then(|| a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x))
        })
        .collect();
    xs.sort_by(f64::total_cmp);
    xs
}

fn draw(s: &Scenario, res: f64) -> Result<Image, String> {
    let (lo, hi) = s.area.bounding_box();
    // One unknown pixel around the area, as a map's edge usually is.
    let origin = Point::new(lo.x - res, lo.y - res);
    let width = ((hi.x - lo.x) / res).ceil() + 2.0;
    let height = ((hi.y - lo.y) / res).ceil() + 2.0;
    if width * height > MAX_IMAGE_PIXELS as f64 {
        return Err(format!(
            "at a resolution of {res} m the image would be {width} x {height} pixels, above the limit \
             MAX_IMAGE_PIXELS = {MAX_IMAGE_PIXELS}: give a coarser --resolution"
        ));
    }
    let (width, height) = (width as usize, height as usize);
    let mut img = Image { width, height, origin, res, pixels: vec![UNKNOWN; width * height] };
    for yb in 0..height {
        img.fill(yb, &crossings(&s.area.points, img.centre_y(yb)), FREE);
    }
    for o in &s.obstacles {
        let (olo, ohi) = o.bounding_box();
        for yb in img.rows(olo.y, ohi.y) {
            let y = img.centre_y(yb);
            let xs = match o {
                Shape::Polygon(p) => crossings(&p.points, y),
                Shape::Circle(c) => {
                    let h = (c.radius * c.radius - (y - c.center.y).powi(2)).max(0.0).sqrt();
                    vec![c.center.x - h, c.center.x + h]
                }
            };
            img.fill(yb, &xs, OCCUPIED);
        }
    }
    Ok(img)
}

/// Writes `s` as map `yaml` with pixels of `res` m: the YAML file, the PGM
/// image beside it (same name, `.pgm`) and the sidecar; the paths written.
pub fn write_map(s: &Scenario, yaml: &Path, res: f64) -> Result<Vec<PathBuf>, String> {
    if !(res.is_finite() && res > 0.0) {
        return Err(format!("the resolution must be a length > 0 m, got {res}"));
    }
    let img = draw(s, res)?;
    let pgm = yaml.with_extension("pgm");
    let side = sidecar_path(yaml);
    let image_name = pgm.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let header = format!("gridswarm export-map: scenario `{}`", shown(&s.name));
    let mut bytes = format!("P5\n# {header}\n{} {}\n255\n", img.width, img.height).into_bytes();
    bytes.extend_from_slice(&img.pixels);
    let mut text = format!("# {header}\n# Targets, starts and parameters: {}\n", side.display());
    let quoted = format!("'{}'", image_name.replace('\'', "''"));
    let _ = write!(
        text,
        "image: {quoted}\nmode: trinary\nresolution: {res:?}\norigin: [{:?}, {:?}, 0.0]\nnegate: 0\n\
         occupied_thresh: 0.65\nfree_thresh: 0.196\n",
        img.origin.x, img.origin.y
    );
    let mut sidecar = s.to_sidecar(&format!("{header}\nThe area and obstacles are in {image_name}."));
    let _ = write!(sidecar, "\n[map]\ncell = {res:?}\nunknown = \"blocked\"\n");
    let write = |path: &Path, data: &[u8]| {
        std::fs::write(path, data).map_err(|e| format!("cannot write `{}`: {e}", path.display()))
    };
    write(&pgm, &bytes)?;
    write(yaml, text.as_bytes())?;
    write(&side, sidecar.as_bytes())?;
    Ok(vec![yaml.to_path_buf(), pgm, side])
}
