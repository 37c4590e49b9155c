//! Reader of Gmsh `.msh` files (ASCII MSH 4.1, and the older ASCII MSH 2.2).
//!
//! A `.msh` file is a sequence of sections, each opened by a line `$Name` and closed by a line
//! `$EndName`; within a section, values are separated by white space. This reader uses:
//!
//! - `$MeshFormat`: `version file-type data-size`; only ASCII (`file-type` 0) versions 4.1 and 2.2
//!   are read, binary files are reported as [`GmshError::Unsupported`].
//! - `$PhysicalNames`: `count`, then `dim tag "name"` lines. A group named twice, one name for two
//!   groups of one dimension, or a name for a group without elements is an error at its line.
//! - `$Entities` (4.1 only): the geometric points, curves, surfaces and volumes with their
//!   physical tags. In 4.1 elements refer to an entity, and the entity to its physical groups.
//! - `$Nodes`: in 4.1, blocks of `dim entity parametric count` followed by the node tags, then one
//!   `x y z [u [v]]` line per node; in 2.2, `count` then `tag x y z` lines. Node tags start at 1.
//! - `$Elements`: in 4.1, blocks of `dim entity type count` followed by `tag node...` lines; in 2.2,
//!   `count` then `tag type ntags tag... node...` lines (the first tag is the physical group).
//!
//! Other sections (`$Comments`, `$NodeData`, `$Periodic`, ...) are skipped.
//!
//! Element types read: 2 (3-node triangle, P1), 9 (6-node triangle, P2: vertices then the mid-side
//! nodes of edges (0,1), (1,2), (2,0), as [`Order::P2`]), 1 (2-node line), 8 (3-node line: ends,
//! then middle) and 15 (point). Quadrilaterals, higher-order and 3D elements are unsupported.
//!
//! The mesh is a set of triangles: those of one physical surface (2D physical group) when
//! [`read_msh_surface`] names one, otherwise all of them, which is an error if the triangles
//! belong to several physical surfaces (several bodies). Node tags are renumbered `0..n` in file
//! order, keeping only nodes used by a chosen triangle; clockwise triangles are reoriented. Every
//! physical group of dimension 1 becomes a named boundary (named by `$PhysicalNames`, or by its
//! tag number), every physical group of dimension 0 a named node set. With a chosen surface, a
//! line or point belongs to the body when all its nodes are nodes of the body, so a physical
//! curve running along two bodies gives each its own part.
//! All coordinates must share one `z` (the mesh lies in a plane parallel to `xy`). 6-node
//! triangles must be straight-sided: the element code maps every triangle affinely (constant
//! barycentric gradients, [`crate::element::Affine`]), so isoparametric triangles would need a
//! point-wise Jacobian in assembly, loads, stresses and the contact geometry. Curved ones (Gmsh's
//! default for `SetOrder(2)` on curved geometry) are reported as [`GmshError::Unsupported`] at
//! their line, naming the two ways out: a P1 mesh promoted to P2 by contactdd, or the gmsh option
//! `Mesh.SecondOrderLinear = 1`.
//!
//! Why this reader lives in the numerical core while every other file format lives in
//! `contactdd-io`: it is a mesh source like [`crate::rectangle`], not a front end. It needs no
//! dependency, builds its result only through the public [`Mesh::new`] (no crate internals), and
//! reports [`GmshError`]; so an MPI driver, a benchmark or a Rust user can read a Gmsh mesh
//! without linking the TOML and JSON code. Nothing else in the core reads or writes files.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

use crate::error::{GmshError, MeshError};
use crate::geometry::{Point, DIM};
use crate::mesh::{counter_clockwise, dist, Edge, Mesh, Order};

/// Reads a Gmsh ASCII mesh file (MSH 4.1 or 2.2) holding one body into a validated [`Mesh`].
pub fn read_msh(path: &Path) -> Result<Mesh, GmshError> {
    read_msh_surface(path, None)
}

/// Reads the body of physical surface `surface` (a name, or a tag number for an unnamed group)
/// of a Gmsh ASCII mesh file; `None` reads a file holding one body. See the module documentation.
pub fn read_msh_surface(path: &Path, surface: Option<&str>) -> Result<Mesh, GmshError> {
    let bytes = std::fs::read(path).map_err(|source| GmshError::Io {
        path: path.display().to_string(),
        source,
    })?;
    // Binary files have an ASCII header, so a lossy conversion still lets `parse_msh` see the
    // file type in `$MeshFormat` and report them as unsupported.
    parse_msh_surface(&String::from_utf8_lossy(&bytes), surface)
}

/// Parses the text of a Gmsh ASCII mesh file (MSH 4.1 or 2.2) holding one body into a validated
/// [`Mesh`].
pub fn parse_msh(text: &str) -> Result<Mesh, GmshError> {
    parse_msh_surface(text, None)
}

/// Parses the body of physical surface `surface` (`None`: the file's only body) of the text of a
/// Gmsh ASCII mesh file into a validated [`Mesh`].
pub fn parse_msh_surface(text: &str, surface: Option<&str>) -> Result<Mesh, GmshError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let raw = RawMsh::parse(text)?;
    raw.build(surface)
}

/// The file format version.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Version {
    V2,
    V4,
}

/// What an element is, for this reader.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Point,
    Line,
    Triangle(Order),
}

/// One element as read, with node tags not yet resolved.
#[derive(Debug)]
struct RawElement {
    /// 1-based line of the element in the file.
    line: usize,
    kind: Kind,
    /// Node tags.
    nodes: Vec<u64>,
    /// MSH 4.1: the (dimension, tag) of the entity the element belongs to.
    entity: Option<(u8, i64)>,
    /// MSH 2.2: the physical tag of the element, if any (0 means none).
    physical: Option<i64>,
}

/// Everything read from the file, before the mesh is assembled.
#[derive(Debug, Default)]
struct RawMsh {
    /// Physical names by (dimension, tag).
    names: HashMap<(u8, i64), String>,
    /// The `$PhysicalNames` line of each name, for errors.
    name_lines: HashMap<(u8, i64), usize>,
    /// Physical tags of each (dimension, entity tag), from `$Entities`.
    entities: HashMap<(u8, i64), Vec<i64>>,
    /// Node coordinates in file order.
    coords: Vec<[f64; 3]>,
    /// Node tag to index into `coords`.
    node_index: HashMap<u64, usize>,
    elements: Vec<RawElement>,
    /// Number of lines of the file (for errors at the end of the file).
    num_lines: usize,
}

/// A cursor over the white-space separated tokens of the file, tracking line numbers.
struct Tokens<'a> {
    lines: Vec<&'a str>,
    /// 0-based index of the current line.
    line: usize,
    /// Byte offset in the current line.
    pos: usize,
    /// Name of the section being read, for end-of-file messages.
    section: &'static str,
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str) -> Self {
        Tokens {
            lines: text.lines().collect(),
            line: 0,
            pos: 0,
            section: "",
        }
    }

    fn error(&self, line: usize, message: impl Into<String>) -> GmshError {
        GmshError::Parse {
            line,
            message: message.into(),
        }
    }

    /// The next token and its 1-based line, or `None` at the end of the file.
    fn next_opt(&mut self) -> Option<(usize, &'a str)> {
        while let Some(&text) = self.lines.get(self.line) {
            let rest = text.get(self.pos..).unwrap_or("");
            let trimmed = rest.trim_start();
            if trimmed.is_empty() {
                self.line += 1;
                self.pos = 0;
                continue;
            }
            let start = self.pos + (rest.len() - trimmed.len());
            let len = trimmed.find(char::is_whitespace).unwrap_or(trimmed.len());
            self.pos = start + len;
            return Some((self.line + 1, &trimmed[..len]));
        }
        None
    }

    /// The next token; the end of the file is an error.
    fn next(&mut self) -> Result<(usize, &'a str), GmshError> {
        match self.next_opt() {
            Some(t) => Ok(t),
            None => {
                let message = if self.section.is_empty() {
                    "unexpected end of file".to_string()
                } else {
                    format!(
                        "unexpected end of file in section ${0} (missing $End{0}?)",
                        self.section
                    )
                };
                Err(self.error(self.lines.len() + 1, message))
            }
        }
    }

    /// The rest of the current line (trimmed), moving to the next line.
    fn rest_of_line(&mut self) -> &'a str {
        let rest = match self.lines.get(self.line) {
            Some(text) => text.get(self.pos..).unwrap_or(""),
            None => "",
        };
        self.line += 1;
        self.pos = 0;
        rest.trim()
    }

    /// Parses the next token as `T`, naming `what` in the error message.
    fn parse<T: std::str::FromStr>(&mut self, what: &str) -> Result<T, GmshError> {
        Ok(self.parse_at(what)?.1)
    }

    /// Parses the next token as `T`, and returns it with its 1-based line number.
    fn parse_at<T: std::str::FromStr>(&mut self, what: &str) -> Result<(usize, T), GmshError> {
        let (line, token) = self.next()?;
        match token.parse() {
            Ok(value) => Ok((line, value)),
            Err(_) => Err(self.error(line, format!("expected {what}, found '{token}'"))),
        }
    }

    /// Parses the next token as a count or tag (a non-negative integer).
    fn usize(&mut self, what: &str) -> Result<usize, GmshError> {
        self.parse(what)
    }

    /// Parses the next token as a finite coordinate.
    fn coordinate(&mut self) -> Result<f64, GmshError> {
        Ok(self.coordinate_at()?.1)
    }

    /// Parses the next token as a finite coordinate, and returns it with its 1-based line number.
    fn coordinate_at(&mut self) -> Result<(usize, f64), GmshError> {
        let (line, token) = self.next()?;
        match token.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok((line, x)),
            Ok(_) => Err(self.error(line, format!("non-finite coordinate '{token}'"))),
            Err(_) => Err(self.error(line, format!("expected a coordinate, found '{token}'"))),
        }
    }

    /// Expects the token `$End<section>`.
    fn expect_end(&mut self) -> Result<(), GmshError> {
        let section = self.section;
        let (line, token) = self.next()?;
        if token.strip_prefix("$End") == Some(section) {
            self.section = "";
            Ok(())
        } else {
            Err(self.error(line, format!("expected $End{section}, found '{token}'")))
        }
    }
}

/// Number of nodes of a Gmsh element type, and what it is; unsupported types are errors.
fn element_kind(ty: usize, line: usize) -> Result<(Kind, usize), GmshError> {
    let unsupported = |what: &str| {
        Err(GmshError::Unsupported(format!(
            "line {line}: element type {ty} ({what}); contactdd reads 3- and 6-node triangles \
             with 2- or 3-node boundary lines and points"
        )))
    };
    match ty {
        15 => Ok((Kind::Point, 1)),
        1 => Ok((Kind::Line, 2)),
        8 => Ok((Kind::Line, 3)),
        2 => Ok((Kind::Triangle(Order::P1), 3)),
        9 => Ok((Kind::Triangle(Order::P2), 6)),
        3 | 10 | 16 => unsupported("quadrilateral"),
        4..=7 | 11..=14 | 17..=19 => unsupported("3D element"),
        20..=25 => unsupported("higher-order or incomplete triangle"),
        26..=28 => unsupported("higher-order line"),
        _ => unsupported("unknown or higher-order element"),
    }
}

/// Dimension of an element kind.
fn kind_dim(kind: Kind) -> u8 {
    match kind {
        Kind::Point => 0,
        Kind::Line => 1,
        Kind::Triangle(_) => 2,
    }
}

/// Allocation size for `count` items announced by the file (not trusted for big allocations).
fn capacity(count: usize) -> usize {
    count.min(1 << 16)
}

impl RawMsh {
    fn parse(text: &str) -> Result<RawMsh, GmshError> {
        let mut tokens = Tokens::new(text);
        let mut raw = RawMsh {
            num_lines: tokens.lines.len(),
            ..RawMsh::default()
        };
        let mut format = None;
        let (mut seen_nodes, mut seen_elements) = (false, false);
        while let Some((line, token)) = tokens.next_opt() {
            let Some(version) = format else {
                if token != "$MeshFormat" {
                    return Err(tokens.error(
                        line,
                        format!("not a Gmsh mesh: expected $MeshFormat, found '{token}'"),
                    ));
                }
                tokens.section = "MeshFormat";
                format = Some(read_format(&mut tokens)?);
                tokens.expect_end()?;
                continue;
            };
            let Some(name) = token.strip_prefix('$') else {
                return Err(tokens.error(
                    line,
                    format!("expected a section header such as $Nodes, found '{token}'"),
                ));
            };
            match name {
                "MeshFormat" => {
                    return Err(tokens.error(line, "a second $MeshFormat section"));
                }
                "PhysicalNames" => {
                    tokens.section = "PhysicalNames";
                    raw.read_physical_names(&mut tokens)?;
                }
                "Entities" if version == Version::V4 => {
                    tokens.section = "Entities";
                    raw.read_entities(&mut tokens)?;
                }
                "Nodes" => {
                    if seen_nodes {
                        return Err(tokens.error(line, "a second $Nodes section"));
                    }
                    seen_nodes = true;
                    tokens.section = "Nodes";
                    match version {
                        Version::V4 => raw.read_nodes_v4(&mut tokens)?,
                        Version::V2 => raw.read_nodes_v2(&mut tokens)?,
                    }
                }
                "Elements" => {
                    if seen_elements {
                        return Err(tokens.error(line, "a second $Elements section"));
                    }
                    seen_elements = true;
                    tokens.section = "Elements";
                    match version {
                        Version::V4 => raw.read_elements_v4(&mut tokens)?,
                        Version::V2 => raw.read_elements_v2(&mut tokens)?,
                    }
                }
                _ if name.starts_with("End") => {
                    return Err(tokens.error(line, format!("'{token}' without its section")));
                }
                _ => {
                    skip_section(&mut tokens, line, name)?;
                    continue;
                }
            }
            tokens.expect_end()?;
        }
        let end = raw.num_lines + 1;
        if format.is_none() {
            return Err(tokens.error(end, "not a Gmsh mesh: no $MeshFormat section"));
        }
        if !seen_nodes {
            return Err(tokens.error(end, "no $Nodes section (truncated file?)"));
        }
        if !seen_elements {
            return Err(tokens.error(end, "no $Elements section (truncated file?)"));
        }
        Ok(raw)
    }

    fn read_physical_names(&mut self, tokens: &mut Tokens<'_>) -> Result<(), GmshError> {
        let count = tokens.usize("the number of physical names")?;
        for _ in 0..count {
            let dim = read_dim(tokens)?;
            let (line, tag): (usize, i64) = tokens.parse_at("a physical tag")?;
            let text = tokens.rest_of_line();
            let name = text
                .strip_prefix('"')
                .and_then(|t| t.strip_suffix('"'))
                .unwrap_or(text);
            if name.is_empty() {
                return Err(tokens.error(line, "expected a quoted physical name"));
            }
            // Either would silently merge or drop groups: a boundary would not be what was drawn.
            if let Some(old) = self.names.get(&(dim, tag)) {
                return Err(tokens.error(
                    line,
                    format!("{dim}D physical group {tag} is named twice ('{old}' and '{name}')"),
                ));
            }
            if let Some(((_, other), _)) = self
                .names
                .iter()
                .find(|((d, _), n)| *d == dim && n.as_str() == name)
            {
                return Err(tokens.error(
                    line,
                    format!(
                        "physical name '{name}' is used by two {dim}D groups ({other} and {tag}); \
                         give each group its own name"
                    ),
                ));
            }
            self.names.insert((dim, tag), name.to_string());
            self.name_lines.insert((dim, tag), line);
        }
        Ok(())
    }

    fn read_entities(&mut self, tokens: &mut Tokens<'_>) -> Result<(), GmshError> {
        let mut counts = [0usize; 4];
        for (dim, count) in counts.iter_mut().enumerate() {
            *count = tokens.usize(&format!("the number of {dim}D entities"))?;
        }
        for (dim, &count) in (0u8..).zip(counts.iter()) {
            for _ in 0..count {
                let tag: i64 = tokens.parse("an entity tag")?;
                // Points have a position, other entities a bounding box.
                let reals = if dim == 0 { 3 } else { 6 };
                for _ in 0..reals {
                    tokens.parse::<f64>("a coordinate")?;
                }
                let num_physicals = tokens.usize("the number of physical tags")?;
                let mut physicals = Vec::with_capacity(capacity(num_physicals));
                for _ in 0..num_physicals {
                    physicals.push(tokens.parse::<i64>("a physical tag")?);
                }
                if dim > 0 {
                    let num_bounding = tokens.usize("the number of bounding entities")?;
                    for _ in 0..num_bounding {
                        tokens.parse::<i64>("a bounding entity tag")?;
                    }
                }
                self.entities.insert((dim, tag), physicals);
            }
        }
        Ok(())
    }

    fn add_node(&mut self, line: usize, tag: u64, xyz: [f64; 3]) -> Result<(), GmshError> {
        if tag == 0 {
            // Gmsh numbers nodes from 1; a 0 is a damaged or hand-made file.
            return Err(GmshError::Parse {
                line,
                message: "node tag 0: Gmsh node tags start at 1".to_string(),
            });
        }
        if self.node_index.insert(tag, self.coords.len()).is_some() {
            return Err(GmshError::Parse {
                line,
                message: format!("node tag {tag} appears twice"),
            });
        }
        self.coords.push(xyz);
        Ok(())
    }

    fn read_nodes_v4(&mut self, tokens: &mut Tokens<'_>) -> Result<(), GmshError> {
        let num_blocks = tokens.usize("the number of node blocks")?;
        let (line, num_nodes) = tokens.parse_at::<usize>("the number of nodes")?;
        tokens.usize("the smallest node tag")?;
        tokens.usize("the largest node tag")?;
        for _ in 0..num_blocks {
            let dim = read_dim(tokens)?;
            tokens.parse::<i64>("an entity tag")?;
            let parametric = tokens.usize("the parametric flag (0 or 1)")?;
            let count = tokens.usize("the number of nodes in the block")?;
            let mut tags = Vec::with_capacity(capacity(count));
            for _ in 0..count {
                tags.push(tokens.parse::<u64>("a node tag")?);
            }
            for tag in tags {
                let (line, x) = tokens.coordinate_at()?;
                let xyz = [x, tokens.coordinate()?, tokens.coordinate()?];
                if parametric != 0 {
                    for _ in 0..dim {
                        tokens.parse::<f64>("a parametric coordinate")?;
                    }
                }
                self.add_node(line, tag, xyz)?;
            }
        }
        if self.coords.len() != num_nodes {
            return Err(tokens.error(
                line,
                format!(
                    "the header announces {num_nodes} nodes, the blocks hold {}",
                    self.coords.len()
                ),
            ));
        }
        Ok(())
    }

    fn read_nodes_v2(&mut self, tokens: &mut Tokens<'_>) -> Result<(), GmshError> {
        let count = tokens.usize("the number of nodes")?;
        for _ in 0..count {
            let (line, tag) = tokens.parse_at::<u64>("a node tag")?;
            let xyz = [
                tokens.coordinate()?,
                tokens.coordinate()?,
                tokens.coordinate()?,
            ];
            self.add_node(line, tag, xyz)?;
        }
        Ok(())
    }

    /// Reads the node tags of one element of `len` nodes.
    fn read_element_nodes(tokens: &mut Tokens<'_>, len: usize) -> Result<Vec<u64>, GmshError> {
        (0..len).map(|_| tokens.parse("a node tag")).collect()
    }

    fn read_elements_v4(&mut self, tokens: &mut Tokens<'_>) -> Result<(), GmshError> {
        let num_blocks = tokens.usize("the number of element blocks")?;
        let (header, num_elements) = tokens.parse_at::<usize>("the number of elements")?;
        tokens.usize("the smallest element tag")?;
        tokens.usize("the largest element tag")?;
        let mut total = 0usize;
        for _ in 0..num_blocks {
            let dim = read_dim(tokens)?;
            let entity: i64 = tokens.parse("an entity tag")?;
            let (line, ty) = tokens.parse_at::<usize>("an element type")?;
            let count = tokens.usize("the number of elements in the block")?;
            if count == 0 {
                continue;
            }
            let (kind, len) = element_kind(ty, line)?;
            if kind_dim(kind) != dim {
                return Err(tokens.error(
                    line,
                    format!("element type {ty} in a block of dimension {dim}"),
                ));
            }
            for _ in 0..count {
                let (line, _) = tokens.parse_at::<u64>("an element tag")?;
                let nodes = Self::read_element_nodes(tokens, len)?;
                self.elements.push(RawElement {
                    line,
                    kind,
                    nodes,
                    entity: Some((dim, entity)),
                    physical: None,
                });
            }
            total = total.saturating_add(count);
        }
        if total != num_elements {
            return Err(tokens.error(
                header,
                format!("the header announces {num_elements} elements, the blocks hold {total}"),
            ));
        }
        Ok(())
    }

    fn read_elements_v2(&mut self, tokens: &mut Tokens<'_>) -> Result<(), GmshError> {
        let count = tokens.usize("the number of elements")?;
        for _ in 0..count {
            let (line, _) = tokens.parse_at::<u64>("an element tag")?;
            let (kind, len) = element_kind(tokens.usize("an element type")?, line)?;
            let num_tags = tokens.usize("the number of element tags")?;
            let mut physical = None;
            for k in 0..num_tags {
                let tag: i64 = tokens.parse("an element tag value")?;
                if k == 0 && tag != 0 {
                    physical = Some(tag);
                }
            }
            let nodes = Self::read_element_nodes(tokens, len)?;
            self.elements.push(RawElement {
                line,
                kind,
                nodes,
                entity: None,
                physical,
            });
        }
        Ok(())
    }

    /// Physical tags of an element.
    fn physicals<'a>(&'a self, element: &'a RawElement) -> &'a [i64] {
        if let Some(tag) = &element.physical {
            return std::slice::from_ref(tag);
        }
        element
            .entity
            .and_then(|key| self.entities.get(&key))
            .map_or(&[], Vec::as_slice)
    }

    /// Name of physical group `tag` of dimension `dim`.
    fn group_name(&self, dim: u8, tag: i64) -> String {
        self.names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| tag.to_string())
    }

    /// Assembles and validates the mesh: the triangles' order and nodes, the nodes renumbered,
    /// the elements sorted into cells, boundaries and node sets, then [`Mesh::new`].
    fn build(self, surface: Option<&str>) -> Result<Mesh, GmshError> {
        self.check_names_used()?;
        let body = self.surface_tag(surface)?;
        let (order, used) = self.triangle_order_and_nodes(body)?;
        let (nodes, new_index) = self.renumber_nodes(&used)?;
        let (cells, boundaries, node_sets) = self.sort_elements(order, &nodes, &new_index, body)?;
        Mesh::new(nodes, order, cells, boundaries, node_sets).map_err(|e| match e {
            // The element code maps every triangle affinely (crate::element::Affine), so a
            // curved (isoparametric) triangle cannot be represented: say how to avoid one.
            MeshError::CurvedEdge { element } => GmshError::Unsupported(format!(
                "line {}: curved 6-node triangle (a mid-side node off its edge's midpoint); \
                 contactdd's P2 triangles are straight-sided. Mesh with order 1 and promote to \
                 P2 in contactdd (mesh key order = \"p2\"), or keep order 2 with straight sides \
                 (gmsh -setnumber Mesh.SecondOrderLinear 1)",
                self.triangle_line(element, body)
            )),
            e => GmshError::Mesh(e),
        })
    }

    /// The file line of triangle `index` of the body (0 if there is no such triangle).
    fn triangle_line(&self, index: usize, body: Option<i64>) -> usize {
        self.elements
            .iter()
            .filter(|e| self.in_body(e, body))
            .nth(index)
            .map_or(0, |e| e.line)
    }

    /// The 2D physical tags the triangles belong to.
    fn surface_tags(&self) -> BTreeSet<i64> {
        self.elements
            .iter()
            .filter(|e| matches!(e.kind, Kind::Triangle(_)))
            .flat_map(|e| self.physicals(e).iter().copied())
            .collect()
    }

    /// The physical surface whose triangles make the body: the one named `surface`, or `None`
    /// (every triangle) when no surface is named and the file has at most one physical surface.
    fn surface_tag(&self, surface: Option<&str>) -> Result<Option<i64>, GmshError> {
        let tags = self.surface_tags();
        let names: Vec<String> = tags.iter().map(|&t| self.group_name(2, t)).collect();
        let listed = if names.is_empty() {
            "the file has no physical surface".to_string()
        } else {
            format!("physical surfaces: {}", names.join(", "))
        };
        match surface {
            Some(name) => match tags.iter().find(|&&t| self.group_name(2, t) == name) {
                Some(&tag) => Ok(Some(tag)),
                None => Err(GmshError::Surface(format!(
                    "no physical surface named '{name}' ({listed})"
                ))),
            },
            None if tags.len() > 1 => Err(GmshError::Surface(format!(
                "the file holds {} bodies ({listed}); name the body's physical surface",
                tags.len()
            ))),
            None => Ok(None),
        }
    }

    /// Whether `element` is a triangle of the body (`body`: its physical surface, `None`: all).
    fn in_body(&self, element: &RawElement, body: Option<i64>) -> bool {
        let chosen = match body {
            Some(tag) => self.physicals(element).contains(&tag),
            None => true,
        };
        matches!(element.kind, Kind::Triangle(_)) && chosen
    }

    /// Checks that every `$PhysicalNames` entry names a group some element belongs to: a name
    /// with a mistyped tag would otherwise leave its boundary unnamed (called by its number).
    fn check_names_used(&self) -> Result<(), GmshError> {
        let mut used = BTreeSet::new();
        for element in &self.elements {
            let dim = kind_dim(element.kind);
            used.extend(self.physicals(element).iter().map(|&tag| (dim, tag)));
        }
        let unused = self
            .name_lines
            .iter()
            .filter(|(key, _)| !used.contains(*key))
            .min_by_key(|(_, &line)| line);
        match unused {
            Some((&(dim, tag), &line)) => Err(GmshError::Parse {
                line,
                message: format!(
                    "physical name '{}' is given to {dim}D group {tag}, which has no elements",
                    self.group_name(dim, tag)
                ),
            }),
            None => Ok(()),
        }
    }

    /// The index in `coords` of node `tag` of `element`.
    fn node_position(&self, element: &RawElement, tag: u64) -> Result<usize, GmshError> {
        self.node_index
            .get(&tag)
            .copied()
            .ok_or_else(|| GmshError::Parse {
                line: element.line,
                message: format!("element refers to node {tag}, which is not in $Nodes"),
            })
    }

    /// Whether every node of `element` is a node of the body (`new_index` is set).
    fn touches(&self, element: &RawElement, new_index: &[usize]) -> bool {
        element.nodes.iter().all(|&tag| {
            self.node_index
                .get(&tag)
                .and_then(|&i| new_index.get(i))
                .is_some_and(|&n| n != usize::MAX)
        })
    }

    /// The order of the triangles (all the same) and, per node of `coords`, whether a triangle
    /// uses it.
    fn triangle_order_and_nodes(&self, body: Option<i64>) -> Result<(Order, Vec<bool>), GmshError> {
        let mut order = None;
        let mut used = vec![false; self.coords.len()];
        for element in &self.elements {
            let Kind::Triangle(o) = element.kind else {
                continue;
            };
            if !self.in_body(element, body) {
                continue;
            }
            match order {
                None => order = Some(o),
                Some(first) if first != o => {
                    return Err(GmshError::Unsupported(format!(
                        "line {}: the mesh mixes 3-node and 6-node triangles",
                        element.line
                    )));
                }
                Some(_) => {}
            }
            for &tag in &element.nodes {
                let i = self.node_position(element, tag)?;
                if let Some(u) = used.get_mut(i) {
                    *u = true;
                }
            }
        }
        let Some(order) = order else {
            // Gmsh saves only the elements of physical groups once a model defines any: a model
            // with physical curves but no physical surface comes out without triangles.
            return Err(GmshError::Unsupported(
                "the file has no triangles (3- or 6-node); contactdd needs a 2D triangle mesh. \
                 When a model has physical groups, Gmsh saves only their elements: add a physical \
                 surface for each body (Physical Surface(\"name\") = {...}), or set \
                 Mesh.SaveAll = 1"
                    .to_string(),
            ));
        };
        Ok((order, used))
    }

    /// Renumbers the `used` nodes in file order and checks that they lie in one xy plane.
    /// Returns their xy coordinates and, per node of `coords`, its new index (`usize::MAX` if
    /// unused).
    fn renumber_nodes(&self, used: &[bool]) -> Result<(Vec<Point>, Vec<usize>), GmshError> {
        let mut new_index = vec![usize::MAX; self.coords.len()];
        let mut nodes = Vec::new();
        let (mut zmin, mut zmax) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut lo, mut hi) = ([f64::INFINITY; DIM], [f64::NEG_INFINITY; DIM]);
        for ((&xyz, &u), slot) in self.coords.iter().zip(used).zip(&mut new_index) {
            if u {
                *slot = nodes.len();
                nodes.push(std::array::from_fn::<f64, DIM, _>(|d| xyz[d]));
                zmin = zmin.min(xyz[2]);
                zmax = zmax.max(xyz[2]);
                for d in 0..DIM {
                    lo[d] = lo[d].min(xyz[d]);
                    hi[d] = hi[d].max(xyz[d]);
                }
            }
        }
        let diameter = dist(hi, lo);
        if zmax - zmin > 1e-10 * diameter {
            return Err(GmshError::Unsupported(format!(
                "the mesh is not planar in xy: z ranges from {zmin} to {zmax}"
            )));
        }
        Ok((nodes, new_index))
    }

    /// Sorts the elements, in the new node numbering, into the flat triangle connectivity
    /// (clockwise triangles reoriented), the named boundaries (lines) and node sets (points).
    fn sort_elements(
        &self,
        order: Order,
        nodes: &[Point],
        new_index: &[usize],
        body: Option<i64>,
    ) -> Result<
        (
            Vec<usize>,
            BTreeMap<String, Vec<Edge>>,
            BTreeMap<String, Vec<usize>>,
        ),
        GmshError,
    > {
        let mut cells = Vec::new();
        let mut boundaries: BTreeMap<String, Vec<Edge>> = BTreeMap::new();
        let mut node_sets: BTreeMap<String, BTreeSet<usize>> = BTreeMap::new();
        for element in &self.elements {
            if matches!(element.kind, Kind::Triangle(_)) && !self.in_body(element, body) {
                continue;
            }
            // A line or point of another body of the file does not touch this one.
            if body.is_some() && !self.touches(element, new_index) {
                continue;
            }
            let mut ids = Vec::with_capacity(element.nodes.len());
            for &tag in &element.nodes {
                let i = self.node_position(element, tag)?;
                let id = new_index.get(i).copied().filter(|&n| n != usize::MAX);
                ids.push(id.ok_or_else(|| GmshError::Parse {
                    line: element.line,
                    message: format!(
                        "element refers to node {tag}, which is not a node of any triangle"
                    ),
                })?);
            }
            match (element.kind, ids.as_slice()) {
                (Kind::Triangle(_), _) => {
                    let start = cells.len();
                    cells.extend_from_slice(&ids);
                    counter_clockwise(nodes, order, &mut cells[start..]);
                }
                (Kind::Line, &[a, b, ref mid @ ..]) => {
                    let mid = match (order, mid) {
                        (Order::P2, &[m]) => Some(m),
                        (Order::P2, _) | (Order::P1, &[]) => None,
                        (Order::P1, _) => {
                            return Err(GmshError::Unsupported(format!(
                                "line {}: 3-node boundary line in a mesh of 3-node triangles",
                                element.line
                            )));
                        }
                    };
                    for &tag in self.physicals(element) {
                        boundaries
                            .entry(self.group_name(1, tag))
                            .or_default()
                            .push(Edge { a, b, mid });
                    }
                }
                (Kind::Point, &[p]) => {
                    for &tag in self.physicals(element) {
                        node_sets
                            .entry(self.group_name(0, tag))
                            .or_default()
                            .insert(p);
                    }
                }
                _ => {
                    return Err(GmshError::Parse {
                        line: element.line,
                        message: "element with a wrong number of nodes".to_string(),
                    });
                }
            }
        }
        let node_sets = node_sets
            .into_iter()
            .map(|(name, set)| (name, set.into_iter().collect()))
            .collect();
        Ok((cells, boundaries, node_sets))
    }
}

/// Reads `$MeshFormat` content: version, file type and data size.
fn read_format(tokens: &mut Tokens<'_>) -> Result<Version, GmshError> {
    let (line, version) = tokens.next()?;
    let version = match version {
        "4.1" => Version::V4,
        // Older 2.x files differ in details this reader does not check: only 2.2 is read.
        "2.2" => Version::V2,
        other => {
            return Err(GmshError::Unsupported(format!(
                "line {line}: MSH format version {other}; save the mesh as version 4.1 or 2.2 \
                 ASCII (gmsh -format msh41)"
            )))
        }
    };
    let (line, file_type) = tokens.next()?;
    match file_type {
        "0" => {}
        "1" => {
            return Err(GmshError::Unsupported(format!(
                "line {line}: binary MSH file; save the mesh as ASCII (gmsh -format msh41, \
                 without -bin)"
            )))
        }
        other => {
            return Err(tokens.error(
                line,
                format!("expected file type 0 (ASCII), found '{other}'"),
            ))
        }
    }
    tokens.usize("the data size")?;
    Ok(version)
}

/// Reads an entity dimension (0 to 3).
fn read_dim(tokens: &mut Tokens<'_>) -> Result<u8, GmshError> {
    let (line, token) = tokens.next()?;
    match token.parse::<u8>() {
        Ok(dim) if dim <= 3 => Ok(dim),
        _ => Err(tokens.error(
            line,
            format!("expected a dimension (0 to 3), found '{token}'"),
        )),
    }
}

/// Skips an unknown section up to its `$End` line.
fn skip_section(tokens: &mut Tokens<'_>, start: usize, name: &str) -> Result<(), GmshError> {
    let end = format!("$End{name}");
    // Skip whole lines: unknown sections may hold quoted strings.
    loop {
        if tokens.line >= tokens.lines.len() {
            return Err(tokens.error(start, format!("section ${name} is not closed by {end}")));
        }
        if tokens.rest_of_line() == end {
            return Ok(());
        }
    }
}
