//! Reading a result folder back for `contactdd plot`: `summary.json` (tolerance, units, the file
//! list, the pairs' friction laws), `contact.csv`, `history.csv`, `steps.csv` and the CSV of a sweep (formats in
//! docs/outputs.md). The folder is user input: every malformed file gives an error naming it.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use contactdd_io::result_set::read_result_file;
pub use contactdd_io::result_set::{TEXT_LIMIT, VTU_LIMIT};
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
    /// Reads a CSV file (RFC 4180 quoting, the `csv` crate's reader) by [`read_text`], at most
    /// [`TEXT_LIMIT`] bytes.
    pub fn read(path: &Path) -> Result<Table> {
        let text = read_text(path, TEXT_LIMIT)?;
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
    /// The space dimension: 3 for a result in space (`"dimension": 3`), else 2.
    pub dimension: u8,
    /// Each pair's name with its `normal_force` and `peak_pressure`, when recorded.
    pub totals: Vec<PairTotals>,
}

/// What `summary.json` records of a pair's pressure: its resultant and its peak.
pub struct PairTotals {
    /// The pair's name.
    pub name: String,
    /// The resultant normal force Σ w p.
    pub normal_force: Option<f64>,
    /// The largest contact pressure.
    pub peak_pressure: Option<f64>,
}

impl Summary {
    /// Reads `dir/summary.json` (a folder without it holds no complete result), checking the type
    /// of every key it uses: a summary that is not a JSON object, has no `files` list, or holds a
    /// key of another type (`"contact": "x"`) is an error naming the file and the key.
    pub fn read(dir: &Path) -> Result<Summary> {
        let path = dir.join("summary.json");
        let text = match read_text(&path, TEXT_LIMIT) {
            Err(e) if is_not_found(&e) => bail!(
                "'{}' has no summary.json: not a complete result folder (see docs/outputs.md)",
                dir.display()
            ),
            other => other?,
        };
        let json: Value = serde_json::from_str(&text)
            .with_context(|| format!("'{}' is not valid JSON", path.display()))?;
        let Some(object) = json.as_object() else {
            bail!(
                "'{}' is {}, not a JSON object: not a summary written by contactdd \
                 (see docs/outputs.md)",
                path.display(),
                kind(&json)
            );
        };
        let keys = Keys {
            path: &path,
            object,
        };
        if keys.get("files").is_none() {
            bail!(
                "'{}' has no file list ('files'): not a result folder of contactdd \
                 (see docs/outputs.md)",
                path.display()
            );
        }
        let files = keys.items("files", "a file name", |_, v| Some(v.as_str()?.to_string()))?;
        let name = |k: &Keys, v: &Value| -> Option<String> {
            let o = v.as_object()?;
            k.with(o).string("name").ok()?
        };
        let bodies = keys.items("bodies", "a body with a \"name\"", name)?;
        let friction = keys.items("contact", "a pair with a \"name\"", |k, p| {
            Some((name(k, p)?, p.get("friction").cloned()))
        })?;
        let friction = friction
            .into_iter()
            .filter_map(|(pair, law)| Some((pair, law?)))
            .collect();
        let dimension = keys.dimension()?;
        // Only a summary in space records the totals read for its figures.
        let in_space = |k: &Keys, p: &Value| match dimension {
            3 => Some(Some((name(k, p)?, p.as_object()?.clone()))),
            _ => Some(None),
        };
        let totals = keys.items("contact", "a pair with a \"name\"", in_space)?;
        let totals = totals
            .into_iter()
            .flatten()
            .map(|(name, pair)| {
                let k = keys.with(&pair);
                Ok(PairTotals {
                    name,
                    normal_force: k.number("normal_force")?,
                    peak_pressure: k.number("peak_pressure")?,
                })
            })
            .collect::<Result<_>>()?;
        Ok(Summary {
            tol: keys.number("tol")?,
            stop_measure: keys.string("stop_measure")?,
            units: keys.string("units")?,
            files,
            bodies,
            steps: keys.items("steps", "a load step", |_, _| Some(()))?.len(),
            monitor: keys.monitor()?,
            friction,
            dimension,
            totals,
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

/// The text of `path`, a file of a result folder (or a sweep's CSV), read by
/// [`read_result_file`]: a regular file itself (no symbolic link is followed, no FIFO or device
/// opened) of at most `limit` bytes, in UTF-8.
pub fn read_text(path: &Path, limit: u64) -> Result<String> {
    let bytes = read_result_file(path, limit)?;
    String::from_utf8(bytes).map_err(|e| {
        anyhow!(
            "'{}' is not UTF-8 text (byte {})",
            path.display(),
            e.utf8_error().valid_up_to()
        )
    })
}

/// True if `e` is an I/O error "not found".
fn is_not_found(e: &anyhow::Error) -> bool {
    e.downcast_ref::<std::io::Error>()
        .is_some_and(|e| e.kind() == std::io::ErrorKind::NotFound)
}

/// What a JSON value is, for messages: "a string", "an array", ….
fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// The keys of a JSON object of `path`, read with their types checked. A missing key and `null`
/// (how the summary writes a value it does not have) are both "absent".
struct Keys<'a> {
    path: &'a Path,
    object: &'a serde_json::Map<String, Value>,
}

impl<'a> Keys<'a> {
    /// The same file, another object in it.
    fn with<'b>(&self, object: &'b serde_json::Map<String, Value>) -> Keys<'b>
    where
        'a: 'b,
    {
        Keys {
            path: self.path,
            object,
        }
    }

    /// The value of `key`, `None` when absent or `null`.
    fn get(&self, key: &str) -> Option<&'a Value> {
        self.object.get(key).filter(|v| !v.is_null())
    }

    /// The error of `key` holding `v` where `expected` belongs.
    fn wrong(&self, key: &str, v: &Value, expected: &str) -> anyhow::Error {
        anyhow!(
            "'{}': \"{key}\" is {}, expected {expected}",
            self.path.display(),
            kind(v)
        )
    }

    /// The number `key`, if present.
    fn number(&self, key: &str) -> Result<Option<f64>> {
        self.get(key)
            .map(|v| v.as_f64().ok_or_else(|| self.wrong(key, v, "a number")))
            .transpose()
    }

    /// The string `key`, if present.
    fn string(&self, key: &str) -> Result<Option<String>> {
        self.get(key)
            .map(|v| {
                v.as_str()
                    .map(String::from)
                    .ok_or_else(|| self.wrong(key, v, "a string"))
            })
            .transpose()
    }

    /// The items of the array `key` (empty if absent), each read by `item`; `None` from it is
    /// an error saying the item is not `what`.
    fn items<T>(
        &self,
        key: &str,
        what: &str,
        item: impl Fn(&Keys<'a>, &'a Value) -> Option<T>,
    ) -> Result<Vec<T>> {
        let Some(value) = self.get(key) else {
            return Ok(Vec::new());
        };
        let array = value
            .as_array()
            .ok_or_else(|| self.wrong(key, value, &format!("an array, each item {what}")))?;
        let at = |i: usize, v: &Value| {
            anyhow!(
                "'{}': \"{key}\" item {} is {}, expected {what}",
                self.path.display(),
                i + 1,
                kind(v)
            )
        };
        array
            .iter()
            .enumerate()
            .map(|(i, v)| item(self, v).ok_or_else(|| at(i, v)))
            .collect()
    }

    /// The space dimension `dimension`: 2 when absent (a planar result), else 2 or 3.
    fn dimension(&self) -> Result<u8> {
        match self.number("dimension")? {
            None => Ok(2),
            Some(d) if d == 2.0 || d == 3.0 => Ok(d as u8),
            Some(d) => bail!(
                "'{}': \"dimension\" is {d}, expected 2 or 3",
                self.path.display()
            ),
        }
    }

    /// The monitored boundary `monitor: {"body", "boundary"}`, if present.
    fn monitor(&self) -> Result<Option<String>> {
        let Some(value) = self.get("monitor") else {
            return Ok(None);
        };
        let expected = "an object with \"body\" and \"boundary\"";
        let object = value
            .as_object()
            .ok_or_else(|| self.wrong("monitor", value, expected))?;
        let keys = self.with(object);
        match (keys.string("body")?, keys.string("boundary")?) {
            (Some(body), Some(boundary)) => Ok(Some(monitor_name(&body, &boundary))),
            _ => Err(self.wrong("monitor", value, expected)),
        }
    }
}

/// The axis units taken from a units note such as `"cm, N/cm^2"`.
#[derive(Clone, Debug, Default)]
pub struct Units {
    /// Length unit (`cm`).
    pub length: Option<String>,
    /// Stress unit (`N/cm^2`).
    pub stress: Option<String>,
    /// Whether the results are in space, where a force is a stress times an area (not a
    /// length).
    pub space: bool,
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
                space: false,
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
    ///
    /// In space, stress × area ([`space_force_unit`]).
    pub fn force(&self) -> Option<String> {
        let (stress, length) = (self.stress.as_deref()?, self.length.as_deref()?);
        match self.space {
            true => Some(space_force_unit(stress, length)),
            false => Some(force_unit(stress, length)),
        }
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

/// The unit of a force in space: stress × length², simplified where the stress is a force per
/// area of that length (`N/mm^2` with `mm`: `N`) or a named unit (`MPa` with `mm`: `N`, `Pa`
/// with `m`: `N`), else written as the product `stress·length²`.
pub fn space_force_unit(stress: &str, length: &str) -> String {
    const NAMED: [(&str, &str, &str); 9] = [
        ("Pa", "m", "N"),
        ("kPa", "m", "kN"),
        ("MPa", "m", "MN"),
        ("GPa", "m", "GN"),
        ("MPa", "mm", "N"),
        ("GPa", "mm", "kN"),
        ("kPa", "mm", "mN"),
        ("psi", "in", "lbf"),
        ("ksi", "in", "kip"),
    ];
    if let Some((_, _, force)) = NAMED.iter().find(|(s, l, _)| *s == stress && *l == length) {
        return (*force).to_string();
    }
    match per_area(stress, length) {
        Some(force) => force.to_string(),
        None => format!("{stress}·{length}²"),
    }
}

/// The unit of stress × length (see [`Units::force`]).
fn force_unit(stress: &str, length: &str) -> String {
    if let Some((_, _, force)) = NAMED.iter().find(|(s, l, _)| *s == stress && *l == length) {
        return (*force).to_string();
    }
    // "F/L^2" times L is F/L.
    match per_area(stress, length) {
        Some(force) => format!("{force}/{length}"),
        None => format!("{stress}·{length}"),
    }
}

/// F of a stress unit written "F/L^2" (or F/L², F/L2, F/(L^2)) with L the length unit.
fn per_area<'a>(stress: &'a str, length: &str) -> Option<&'a str> {
    let (force, area) = stress.rsplit_once('/')?;
    let area = area.trim();
    let area = (area.strip_prefix('(').and_then(|a| a.strip_suffix(')'))).unwrap_or(area);
    let squared = ["^2", "²", "2"]
        .iter()
        .any(|two| area.strip_suffix(two).map(str::trim) == Some(length));
    let force = force.trim();
    (squared && !force.is_empty()).then_some(force)
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
