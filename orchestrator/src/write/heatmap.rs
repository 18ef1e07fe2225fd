//! A heat map of labelled cells as SVG: rows against columns, each cell a
//! colour and a short text, with a legend of what the colours mean. The
//! readings experiment draws its claims against the readings with it.

use plotters::prelude::*;

use crate::plot::TEXT;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One cell: its fill and the text written in it.
#[derive(Clone, Debug)]
pub struct Cell {
    pub fill: RGBColor,
    pub text: String,
}

/// What to draw. `cells[row][column]`; rows and columns as labelled.
#[derive(Clone, Debug, Default)]
pub struct Heat {
    pub title: String,
    /// Under the column labels, naming what the columns are.
    pub columns_desc: String,
    pub columns: Vec<String>,
    pub rows: Vec<String>,
    pub cells: Vec<Vec<Cell>>,
    /// The colours' meanings, drawn under the map.
    pub legend: Vec<(RGBColor, String)>,
}

const CELL_W: i32 = 92;
const CELL_H: i32 = 30;
const LEFT: i32 = 230;
const TOP: i32 = 78;

/// The map as an SVG document.
pub fn svg(h: &Heat) -> Result<String, String> {
    let (nc, nr) = (h.columns.len() as i32, h.rows.len() as i32);
    let width = (LEFT + nc * CELL_W + 20).max(520) as u32;
    let height = (TOP + nr * CELL_H + 40 + 22 * h.legend.len() as i32) as u32;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (width, height)).into_drawing_area();
        let e = |e: DrawingAreaErrorKind<_>| e.to_string();
        root.fill(&WHITE).map_err(e)?;
        let centred =
            |size: u32| ("sans-serif", size).into_font().color(&BLACK).pos(Pos::new(HPos::Center, VPos::Center));
        let right = ("sans-serif", TEXT).into_font().color(&BLACK).pos(Pos::new(HPos::Right, VPos::Center));
        let left = ("sans-serif", TEXT).into_font().color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center));
        root.draw(&Text::new(h.title.clone(), (width as i32 / 2, 16), centred(20))).map_err(e)?;
        let mid = LEFT + nc * CELL_W / 2;
        root.draw(&Text::new(h.columns_desc.clone(), (mid, 40), centred(TEXT))).map_err(e)?;
        for (c, label) in h.columns.iter().enumerate() {
            let x = LEFT + c as i32 * CELL_W + CELL_W / 2;
            root.draw(&Text::new(label.clone(), (x, TOP - 14), centred(TEXT))).map_err(e)?;
        }
        for (r, label) in h.rows.iter().enumerate() {
            let y = TOP + r as i32 * CELL_H;
            root.draw(&Text::new(label.clone(), (LEFT - 8, y + CELL_H / 2), right.clone())).map_err(e)?;
            for (c, cell) in h.cells.get(r).into_iter().flatten().enumerate() {
                let x = LEFT + c as i32 * CELL_W;
                let rect = [(x + 1, y + 1), (x + CELL_W - 1, y + CELL_H - 1)];
                root.draw(&Rectangle::new(rect, cell.fill.filled())).map_err(e)?;
                let text = ("sans-serif", TEXT).into_font().color(&WHITE).pos(Pos::new(HPos::Center, VPos::Center));
                root.draw(&Text::new(cell.text.clone(), (x + CELL_W / 2, y + CELL_H / 2), text)).map_err(e)?;
            }
        }
        let y0 = TOP + nr * CELL_H + 24;
        for (k, (fill, what)) in h.legend.iter().enumerate() {
            let y = y0 + 22 * k as i32;
            root.draw(&Rectangle::new([(LEFT, y - 7), (LEFT + 22, y + 7)], fill.filled())).map_err(e)?;
            root.draw(&Text::new(what.clone(), (LEFT + 30, y), left.clone())).map_err(e)?;
        }
        root.present().map_err(e)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_labels_and_legend_are_drawn() {
        let h = Heat {
            title: "t".into(),
            columns_desc: "LFP turn".into(),
            columns: vec!["σ 0.5".into(), "uniform".into()],
            rows: vec!["(a)".into()],
            cells: vec![vec![
                Cell { fill: RGBColor(1, 2, 3), text: "holds".into() },
                Cell { fill: RGBColor(4, 5, 6), text: "fails".into() },
            ]],
            legend: vec![(RGBColor(1, 2, 3), "green: holds".into())],
        };
        let s = svg(&h).unwrap();
        for needle in ["holds", "fails", "uniform", "(a)", "green: holds", "#010203", "#040506"] {
            assert!(s.contains(needle), "{needle} missing");
        }
    }
}
