//! Reading a result folder back for `contactdd plot`: `summary.json` (tolerance, units, the file
//! list, the pairs' friction laws), `contact.csv`, `history.csv`, `steps.csv` and the CSV of a sweep (formats in
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
    /// What the stopping test compares with the tolerance (`relative residual`, …), when the
    /// summary records it.
    pub stop_measure: Option<String>,
    /// The problem's units note, when the summary records it.
    pub units: Option<String>,
    /// The files of the result set (the reader's rule of docs/outputs.md).
    pub files: Vec<String>,
    /// The bodies' names, in the order of the problem.
    pub bodies: Vec<String>,
    /// The number of load steps solved (0 without load steps).
    pub steps: usize,
    /// The monitored boundary as "top of upper", when the summary records it.
    pub monitor: Option<String>,
    /// The friction law of each frictional pair: its name and its `contact[].friction` object
    /// as written (read by the friction figure, which checks it).
    pub friction: Vec<(String, Value)>,
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
        let strings = |v: &Value| -> Vec<String> {
            v.as_array()
                .map(|a| a.iter().filter_map(|f| f.as_str().map(String::from)))
                .map(Iterator::collect)
                .unwrap_or_default()
        };
        let bodies = json["bodies"].as_array().map(|a| {
            a.iter()
                .filter_map(|b| b["name"].as_str().map(String::from))
                .collect()
        });
        let monitor = &json["monitor"];
        let monitor = match (monitor["body"].as_str(), monitor["boundary"].as_str()) {
            (Some(body), Some(boundary)) => Some(monitor_name(body, boundary)),
            _ => None,
        };
        let friction = json["contact"].as_array().map(|pairs| {
            pairs
                .iter()
                .filter_map(|p| Some((p["name"].as_str()?.to_string(), p.get("friction")?.clone())))
                .collect()
        });
        Ok(Summary {
            tol: json["tol"].as_f64(),
            stop_measure: json["stop_measure"].as_str().map(String::from),
            units: json["units"].as_str().map(String::from),
            files: strings(&json["files"]),
            bodies: bodies.unwrap_or_default(),
            steps: json["steps"].as_array().map_or(0, Vec::len),
            monitor,
            friction: friction.unwrap_or_default(),
        })
    }

    /// True if the result set lists `name` (a plain file name: the reader's rule ignores any
    /// other, such as `../x` or `/etc/x`).
    pub fn has(&self, name: &str) -> bool {
        plain(name) && self.files.iter().any(|f| f == name)
    }

    /// The listed files whose names end in `suffix`, plain file names only.
    pub fn listed(&self, suffix: &str) -> Vec<String> {
        let keep = |f: &&String| plain(f) && f.ends_with(suffix);
        self.files.iter().filter(keep).cloned().collect()
    }
}

/// How a monitored boundary is named on a figure: "top of upper".
pub fn monitor_name(body: &str, boundary: &str) -> String {
    format!("{boundary} of {body}")
}

/// True if `name` is a plain file name: one component, no folder, not `.` or `..`.
fn plain(name: &str) -> bool {
    let mut parts = Path::new(name).components();
    matches!(
        (parts.next(), parts.next()),
        (Some(std::path::Component::Normal(_)), None)
    ) && !name.contains(['/', '\\'])
}

/// `dir/name` for a file of the result set, checked to be a regular file (after links): a
/// device, FIFO or folder under a listed name is refused rather than read (reading `/dev/zero`
/// never ends, a FIFO may block).
pub fn listed_file(dir: &Path, name: &str) -> Result<PathBuf> {
    let path = dir.join(name);
    let meta =
        std::fs::metadata(&path).with_context(|| format!("cannot read '{}'", path.display()))?;
    if !meta.is_file() {
        bail!(
            "'{}' is not a regular file; refusing to read it",
            path.display()
        );
    }
    Ok(path)
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

    /// The unit of a force in 2D (per unit thickness): stress × length, simplified where the
    /// stress is a force per area of that length (`N/mm^2`·`mm` = `N/mm`) or a named unit
    /// (`MPa`·`mm` = `N/mm`, `Pa`·`m` = `N/m`), else written as the product `stress·length`.
    pub fn force(&self) -> Option<String> {
        let (stress, length) = (self.stress.as_deref()?, self.length.as_deref()?);
        Some(force_unit(stress, length))
    }
}

/// Named stress units times a length: the force per length they make.
const NAMED: [(&str, &str, &str); 9] = [
    ("Pa", "m", "N/m"),
    ("kPa", "m", "kN/m"),
    ("MPa", "m", "MN/m"),
    ("GPa", "m", "GN/m"),
    ("MPa", "mm", "N/mm"),
    ("GPa", "mm", "kN/mm"),
    ("kPa", "mm", "N/m"),
    ("psi", "in", "lbf/in"),
    ("ksi", "in", "kip/in"),
];

/// The unit of stress × length (see [`Units::force`]).
fn force_unit(stress: &str, length: &str) -> String {
    if let Some((_, _, force)) = NAMED.iter().find(|(s, l, _)| *s == stress && *l == length) {
        return (*force).to_string();
    }
    // "F/L^2" (or F/L², F/L2, F/(L^2)) times L is F/L.
    if let Some((force, area)) = stress.rsplit_once('/') {
        let area = area.trim();
        let area = area
            .strip_prefix('(')
            .and_then(|a| a.strip_suffix(')'))
            .unwrap_or(area);
        let squared = ["^2", "²", "2"]
            .iter()
            .any(|two| area.strip_suffix(two).map(str::trim) == Some(length));
        if squared && !force.trim().is_empty() {
            return format!("{}/{length}", force.trim());
        }
    }
    format!("{stress}·{length}")
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
        assert_eq!(u.force().as_deref(), Some("N/cm"));
        assert!(Units::parse(Some("SI")).length.is_none());
        assert!(Units::parse(None).stress.is_none());
    }

    #[test]
    fn force_units_simplify_where_they_can() {
        for (stress, length, force) in [
            ("N/mm^2", "mm", "N/mm"),
            ("N/mm²", "mm", "N/mm"),
            ("kN/(m^2)", "m", "kN/m"),
            ("MPa", "mm", "N/mm"),
            ("Pa", "m", "N/m"),
            ("MPa", "m", "MN/m"),
            // No simplification known: the product, as it is.
            ("N/cm^2", "mm", "N/cm^2·mm"),
            ("MPa", "cm", "MPa·cm"),
            ("/m^2", "m", "/m^2·m"),
        ] {
            assert_eq!(force_unit(stress, length), force, "{stress} × {length}");
        }
    }

    #[test]
    fn only_plain_names_are_listed() {
        assert!(plain("contact.csv") && plain("a-step1.vtu"));
        for name in ["../x.vtu", "/etc/x.vtu", "sub/x.vtu", ".", "..", ""] {
            assert!(!plain(name), "{name}");
        }
    }
}
