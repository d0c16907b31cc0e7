//! A small Markdown table and the number formats of the generated files.

use crate::stats::quantile::{quantile_sorted, sorted_finite};

/// A Markdown table: a head and rows of cells (a `|` in a cell is escaped when written).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Table {
    /// Column titles.
    pub head: Vec<String>,
    /// Body rows, each as long as `head`.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these column titles and no rows.
    pub fn new(head: &[&str]) -> Table {
        Table {
            head: head.iter().map(|s| s.to_string()).collect(),
            rows: vec![],
        }
    }

    /// Appends a row (shorter rows are padded with empty cells, longer ones cut).
    pub fn row(&mut self, cells: Vec<String>) {
        let mut cells = cells;
        cells.resize(self.head.len(), String::new());
        self.rows.push(cells);
    }

    /// The table as Markdown, one line per row.
    pub fn markdown(&self) -> String {
        let line = |cells: &[String]| {
            let cells: Vec<String> = cells.iter().map(|c| c.replace('|', "\\|")).collect();
            format!("| {} |\n", cells.join(" | "))
        };
        let mut out = line(&self.head);
        out.push_str(&line(&vec!["---".to_string(); self.head.len()]));
        for r in &self.rows {
            out.push_str(&line(r));
        }
        out
    }
}

/// `x` with 3 significant digits (integers of 3 digits or more in full, below 0.001 as
/// `1.23e-5`), "–" if not finite.
pub fn num(x: f64) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    if x.abs() < 1e-3 {
        return format!("{x:.2e}");
    }
    let digits = 3 - 1 - x.abs().log10().floor() as i32;
    if digits <= 0 {
        format!("{:.0}", x)
    } else {
        format!("{:.*}", digits as usize, x)
    }
}

/// A count: `x` rounded to an integer, "–" if not finite.
pub fn int(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.0}")
    } else {
        "–".into()
    }
}

/// The `p`-quantile of the finite values, if there are any.
pub fn quantile(v: &[f64], p: f64) -> Option<f64> {
    let s = sorted_finite(v);
    (!s.is_empty()).then(|| quantile_sorted(&s, p))
}

/// "median / p90" of the finite values, "–" if there are none.
pub fn median_p90(v: &[f64]) -> String {
    match (quantile(v, 0.5), quantile(v, 0.9)) {
        (Some(m), Some(p)) => format!("{} / {}", num(m), num(p)),
        _ => "–".into(),
    }
}

/// The median of the finite values formatted by [`num`], "–" if there are none.
pub fn median(v: &[f64]) -> String {
    quantile(v, 0.5).map(num).unwrap_or_else(|| "–".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_three_significant_digits() {
        assert_eq!(num(0.025_84), "0.0258");
        assert_eq!(num(2.514), "2.51");
        assert_eq!(num(342.4), "342");
        assert_eq!(num(251_331.0), "251331");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(8.67e-15), "8.67e-15");
        assert_eq!(int(23.0), "23");
        assert_eq!(num(f64::NAN), "–");
        assert_eq!(median_p90(&[]), "–");
        assert_eq!(median_p90(&[1.0, 2.0, 3.0]), "2.00 / 2.80");
    }

    #[test]
    fn cells_with_a_bar_do_not_split_the_row() {
        let mut t = Table::new(&["a", "b"]);
        t.row(vec!["x|y".into()]);
        assert_eq!(t.markdown(), "| a | b |\n| --- | --- |\n| x\\|y |  |\n");
    }
}
