//! The one markdown table writer: a header, per-column alignment, rows of cells already
//! formatted. Every report's tables go through it, so a table's shape (a cell per column,
//! the separator row) is checked in one place.

use std::fmt::{self, Display};

/// How a column's cells are aligned (the separator row's colons).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    /// `---` (markdown's default)
    Left,
    /// `---:`
    Right,
    /// `:---:`
    Centre,
}

/// A markdown table under construction.
#[derive(Clone, Debug)]
pub struct Table {
    head: Vec<String>,
    align: Vec<Align>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these column headers, every column left-aligned.
    pub fn new<S: Display>(head: impl IntoIterator<Item = S>) -> Table {
        let head: Vec<String> = head.into_iter().map(|h| h.to_string()).collect();
        Table {
            align: vec![Align::Left; head.len()],
            head,
            rows: Vec::new(),
        }
    }

    /// The same table with column `col` aligned as `a`.
    pub fn align(mut self, col: usize, a: Align) -> Table {
        if let Some(x) = self.align.get_mut(col) {
            *x = a;
        }
        self
    }

    /// Append a row. A row with fewer cells than columns is padded with empty cells; one
    /// with more is a programming error (it would drop a cell silently), so it panics.
    pub fn row<S: Display>(&mut self, cells: impl IntoIterator<Item = S>) -> &mut Table {
        let mut r: Vec<String> = cells.into_iter().map(|c| c.to_string()).collect();
        assert!(
            r.len() <= self.head.len(),
            "a row of {} cells in a table of {} columns",
            r.len(),
            self.head.len()
        );
        r.resize(self.head.len(), String::new());
        self.rows.push(r);
        self
    }

    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    pub fn len(&self) -> usize {
        self.rows.len()
    }
}

/// A cell's text with every `|` not already escaped written `\|`, so a cell holding
/// |x| stays one cell.
fn escaped(c: &str) -> std::borrow::Cow<'_, str> {
    if !c.contains('|') {
        return c.into();
    }
    let mut out = String::with_capacity(c.len() + 4);
    let mut prev = ' ';
    for ch in c.chars() {
        if ch == '|' && prev != '\\' {
            out.push('\\');
        }
        out.push(ch);
        prev = ch;
    }
    out.into()
}

impl Display for Table {
    /// `| h1 | h2 |`, the separator row, one line per row; every line ends in a newline.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let line = |f: &mut fmt::Formatter<'_>, cells: &[String]| -> fmt::Result {
            for c in cells {
                write!(f, "| {} ", escaped(c))?;
            }
            writeln!(f, "|")
        };
        line(f, &self.head)?;
        for a in &self.align {
            f.write_str(match a {
                Align::Left => "|---",
                Align::Right => "|---:",
                Align::Centre => "|:---:",
            })?;
        }
        writeln!(f, "|")?;
        for r in &self.rows {
            line(f, r)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_header_separator_and_padded_rows() {
        let mut t = Table::new(["a", "b", "c"]).align(1, Align::Right);
        t.row(["1", "2", "3"]).row(["x"]);
        assert_eq!(
            t.to_string(),
            "| a | b | c |\n|---|---:|---|\n| 1 | 2 | 3 |\n| x |  |  |\n"
        );
        assert_eq!(t.len(), 2);
    }

    #[test]
    fn a_pipe_in_a_cell_is_escaped_once() {
        let mut t = Table::new(["mean |Δ|", r"\|e\|"]);
        t.row(["|x| + 1", "a|b"]);
        assert_eq!(
            t.to_string(),
            "| mean \\|Δ\\| | \\|e\\| |\n|---|---|\n| \\|x\\| + 1 | a\\|b |\n"
        );
    }
}
