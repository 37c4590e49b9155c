//! Reading a result folder back for `contactdd plot`: `summary.json` (tolerance, units, the file
//! list), `contact.csv`, `history.csv`, `steps.csv` and the CSV of a sweep (formats in
//! docs/outputs.md). The folder is user input: every malformed file gives an error naming it.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use serde_json::Value;

/// A CSV table: the header and the rows, each as text fields.
pub struct Table {
    /// The file it came from, for error messages.
    pub path: PathBuf,
    /// Column names.
    pub header: Vec<String>,
    /// Rows, each as long as the header.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// Reads a CSV file (RFC 4180 quoting, the `csv` crate's reader).
    pub fn read(path: &Path) -> Result<Table> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read '{}'", path.display()))?;
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .from_reader(text.as_bytes());
        let mut records = reader.records();
        let record = |r: Option<csv::Result<csv::StringRecord>>| -> Result<Option<Vec<String>>> {
            r.transpose()
                .with_context(|| format!("'{}' is not valid CSV", path.display()))
                .map(|r| r.map(|r| r.iter().map(String::from).collect()))
        };
        let header = record(records.next())?.unwrap_or_default();
        if header.iter().all(String::is_empty) {
            bail!("'{}' is empty (no header line)", path.display());
        }
        let mut rows = Vec::new();
        while let Some(row) = record(records.next())? {
            if row.len() != header.len() {
                bail!(
                    "'{}' line {}: {} fields, the header has {}",
                    path.display(),
                    rows.len() + 2,
                    row.len(),
                    header.len()
                );
            }
            rows.push(row);
        }
        Ok(Table {
            path: path.to_path_buf(),
            header,
            rows,
        })
    }

    /// The index of the column `name`.
    pub fn column(&self, name: &str) -> Result<usize> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| anyhow!("'{}' has no column '{name}'", self.path.display()))
    }

    /// The number in column `c` of row `r` (`inf`, `-inf` and `NaN` included).
    pub fn number(&self, r: usize, c: usize) -> Result<f64> {
        let text = &self.rows[r][c];
        text.trim().parse::<f64>().map_err(|_| {
            anyhow!(
                "'{}' line {}, column '{}': '{text}' is not a number",
                self.path.display(),
                r + 2,
                self.header[c]
            )
        })
    }

    /// The whole column `name` as numbers.
    pub fn numbers(&self, name: &str) -> Result<Vec<f64>> {
        let c = self.column(name)?;
        (0..self.rows.len()).map(|r| self.number(r, c)).collect()
    }
}

/// What `contactdd plot` needs from `summary.json`.
pub struct Summary {
    /// The stopping tolerance, when the summary records it.
    pub tol: Option<f64>,
    /// The problem's units note, when the summary records it.
    pub units: Option<String>,
    /// The files of the result set (the reader's rule of docs/outputs.md).
    pub files: Vec<String>,
}

impl Summary {
    /// Reads `dir/summary.json`; a folder without it holds no complete result.
    pub fn read(dir: &Path) -> Result<Summary> {
        let path = dir.join("summary.json");
        if !path.is_file() {
            bail!(
                "'{}' has no summary.json: not a complete result folder (see docs/outputs.md)",
                dir.display()
            );
        }
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("cannot read '{}'", path.display()))?;
        let json: Value = serde_json::from_str(&text)
            .with_context(|| format!("'{}' is not valid JSON", path.display()))?;
        let files = json["files"]
            .as_array()
            .map(|a| a.iter().filter_map(|f| f.as_str().map(String::from)));
        Ok(Summary {
            tol: json["tol"].as_f64(),
            units: json["units"].as_str().map(String::from),
            files: files.map(Iterator::collect).unwrap_or_default(),
        })
    }

    /// True if the result set lists `name`.
    pub fn has(&self, name: &str) -> bool {
        self.files.iter().any(|f| f == name)
    }
}

/// The axis units taken from a units note such as `"cm, N/cm^2"`.
#[derive(Clone, Debug, Default)]
pub struct Units {
    /// Length unit (`cm`).
    pub length: Option<String>,
    /// Stress unit (`N/cm^2`).
    pub stress: Option<String>,
}

impl Units {
    /// Reads "length, stress"; any other note gives no units (it is free text).
    pub fn parse(note: Option<&str>) -> Units {
        let parts: Vec<&str> = note
            .map(|n| n.split(',').map(str::trim).collect())
            .unwrap_or_default();
        match parts.as_slice() {
            [l, s] if !l.is_empty() && !s.is_empty() => Units {
                length: Some(l.to_string()),
                stress: Some(s.to_string()),
            },
            _ => Units::default(),
        }
    }

    /// `name (unit)`, or `name` alone without a unit.
    pub fn label(name: &str, unit: Option<&str>) -> String {
        unit.map_or_else(|| name.to_string(), |u| format!("{name} ({u})"))
    }

    /// The unit of a force in 2D (per unit thickness): stress × length.
    pub fn force(&self) -> Option<String> {
        Some(format!(
            "{}·{}",
            self.stress.as_deref()?,
            self.length.as_deref()?
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_fields_are_unquoted_and_may_span_lines() {
        let dir = std::env::temp_dir().join(format!("contactdd-table-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.csv");
        std::fs::write(
            &path,
            "a,b,c\n\"x,y\",\"say \"\"hi\"\"\",\"two\nlines\"\n1,,3\n",
        )
        .unwrap();
        let t = Table::read(&path).unwrap();
        assert_eq!(t.header, ["a", "b", "c"]);
        assert_eq!(
            t.rows,
            [["x,y", "say \"hi\"", "two\nlines"], ["1", "", "3"]]
        );
        std::fs::write(&path, "a,b\n1,2,3\n").unwrap();
        let e = Table::read(&path).err().unwrap().to_string();
        assert!(e.contains("line 2: 3 fields, the header has 2"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn units_notes() {
        let u = Units::parse(Some("cm, N/cm^2"));
        assert_eq!(u.length.as_deref(), Some("cm"));
        assert_eq!(u.force().as_deref(), Some("N/cm^2·cm"));
        assert!(Units::parse(Some("SI")).length.is_none());
        assert!(Units::parse(None).stress.is_none());
    }
}
