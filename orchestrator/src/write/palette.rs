//! The colours of every picture: one list for robots (routes.svg, the
//! replay page) and for the series of the experiments' panels, and the
//! targets' colour, which no robot ever gets.
//!
//! The list is Tableau 10 without its red (the targets') and its grey (the
//! obstacles'), then colours picked greedily from Tableau 20, Kelly's and
//! Okabe-Ito's sets for the largest least distance (CIE76) to those already
//! chosen, none lighter than L* 75 (they must show on the map's pale
//! background). More robots than colours reuse them with a dash pattern
//! per round of the list ([`robot_dash`]).

/// Targets, their sensing circles and the undetected samples of `--grids`.
pub const TARGET: &str = "#d62728";

/// Robot and series colours, in order.
pub const COLOURS: [&str; 24] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#bcbd22", "#17becf", "#8338ec", "#000000",
    "#ff006e", "#637939", "#a6761d", "#93003a", "#f99379", "#004949", "#1b9e77", "#3a86ff", "#00429d", "#490092",
    "#882d17", "#9c9ede", "#7b4173", "#b66dff",
];

/// Robot `r`'s colour (robots numbered from 0, as in the CLI and JSON).
pub fn robot(r: usize) -> &'static str {
    COLOURS[r % COLOURS.len()]
}

/// Robot `r`'s route dash pattern (SVG `stroke-dasharray`): solid for the
/// first round of the list, so that robots sharing a colour still differ.
pub fn robot_dash(r: usize) -> Option<&'static str> {
    const DASHES: [&str; 3] = ["8 4", "2 3", "12 3 2 3"];
    match r / COLOURS.len() {
        0 => None,
        k => Some(DASHES[(k - 1) % DASHES.len()]),
    }
}

/// `#rrggbb` as its three bytes.
pub fn rgb(hex: &str) -> (u8, u8, u8) {
    let byte = |k: usize| u8::from_str_radix(&hex[k..k + 2], 16).expect("a palette colour is #rrggbb");
    (byte(1), byte(3), byte(5))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CIE L*a*b* of an sRGB colour (D65).
    fn lab(hex: &str) -> [f64; 3] {
        let (r, g, b) = rgb(hex);
        let lin = |c: u8| {
            let c = c as f64 / 255.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        let (r, g, b) = (lin(r), lin(g), lin(b));
        let x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047;
        let y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
        let z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883;
        let f = |t: f64| if t > 0.008856 { t.cbrt() } else { 7.787 * t + 16.0 / 116.0 };
        [116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))]
    }

    fn distance(a: &str, b: &str) -> f64 {
        let (p, q) = (lab(a), lab(b));
        (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt()
    }

    #[test]
    fn twenty_distinguishable_colours_none_the_targets() {
        assert!(COLOURS.len() >= 20);
        for (i, a) in COLOURS.iter().enumerate() {
            // 25 CIE76 units apart: clearly different side by side.
            for b in &COLOURS[i + 1..] {
                assert!(distance(a, b) >= 25.0, "{a} and {b} are {:.1} apart", distance(a, b));
            }
            assert!(distance(a, TARGET) >= 30.0, "{a} is {:.1} from the targets' red", distance(a, TARGET));
            assert!(lab(a)[0] <= 75.0, "{a} is too pale for the map's background");
        }
        // Robots 0 and 12 (the `large` map's 13) differ, and none is red.
        assert_ne!(robot(0), robot(12));
        assert!((0..200).all(|r| robot(r) != TARGET));
    }

    #[test]
    fn robots_past_the_list_differ_by_dash() {
        let n = COLOURS.len();
        assert_eq!(robot(0), robot(n));
        assert_eq!(robot_dash(0), None);
        assert_ne!(robot_dash(n), None);
        assert_ne!(robot_dash(n), robot_dash(2 * n));
    }
}
