//! The sections of a `.msh` file read into their raw content: physical names, entities, nodes
//! and elements, with node tags not yet resolved.

use std::collections::HashMap;
use std::ops::Deref;

use crate::error::GmshError;
use crate::fast_hash::FastMap;
use crate::mesh::Order;
use crate::names::{name_problem, shown};

use super::tokens::{read_dim, skip_section, Tokens};

/// The file format version.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Version {
    V2,
    V4,
}

/// What an element is, for this reader.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    Point,
    Line,
    Triangle(Order),
    /// A 4-node (P1) or 10-node (P2) tetrahedron: read by the solid reader only.
    Tetrahedron(Order),
}

/// The space of the mesh the file is read for: the planar reader refuses tetrahedra where they
/// appear, the solid reader takes them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Space {
    /// A planar triangle mesh ([`crate::mesh::Mesh`]).
    Planar,
    /// A tetrahedral mesh ([`crate::solid::SolidMesh`]).
    Solid,
}

/// One element as read, with node tags not yet resolved.
#[derive(Debug)]
pub(super) struct RawElement {
    /// 1-based line of the element in the file.
    pub(super) line: usize,
    /// The element's tag (its number in the file).
    pub(super) tag: u64,
    pub(super) kind: Kind,
    /// Where its node tags start in [`RawMsh::tags`].
    pub(super) first_tag: usize,
    /// Its number of nodes.
    pub(super) num_nodes: u8,
    /// MSH 4.1: the (dimension, tag) of the entity the element belongs to.
    pub(super) entity: Option<(u8, i64)>,
    /// MSH 2.2: the physical tag of the element, if any (0 means none).
    pub(super) physical: Option<i64>,
}

/// Everything read from the file, before the mesh is assembled.
#[derive(Debug, Default)]
pub(super) struct RawMsh {
    /// Physical names by (dimension, tag).
    pub(super) names: FastMap<(u8, i64), String>,
    /// The `$PhysicalNames` line of each name, for errors.
    pub(super) name_lines: FastMap<(u8, i64), usize>,
    /// Physical tags of each (dimension, entity tag), from `$Entities`.
    pub(super) entities: FastMap<(u8, i64), Vec<i64>>,
    /// Node coordinates in file order.
    pub(super) coords: Vec<[f64; 3]>,
    /// Node tag to index into `coords`.
    pub(super) node_index: NodeIndex,
    pub(super) elements: Vec<RawElement>,
    /// The node tags of every element, one after the other (no allocation per element).
    pub(super) tags: Vec<u64>,
    /// Number of lines of the file (for errors at the end of the file).
    pub(super) num_lines: usize,
}

/// Most nodes of an element read (a 10-node tetrahedron).
const MAX_NODES: usize = 10;

/// The nodes of one element (at most [`MAX_NODES`]) in a new numbering, without an allocation of
/// their own.
#[derive(Clone, Copy, Debug)]
pub(super) struct Few<T> {
    items: [T; MAX_NODES],
    len: u8,
}

impl<T: Copy + Default> Few<T> {
    /// No items.
    pub(super) fn new() -> Self {
        Few {
            items: [T::default(); MAX_NODES],
            len: 0,
        }
    }

    /// Appends `item`; the caller keeps to [`MAX_NODES`] items (more would panic).
    pub(super) fn push(&mut self, item: T) {
        self.items[usize::from(self.len)] = item;
        self.len += 1;
    }
}

impl<T> Deref for Few<T> {
    type Target = [T];

    fn deref(&self) -> &[T] {
        &self.items[..usize::from(self.len)]
    }
}

/// Node tag to index into `coords`: a vector indexed by tag while the tags are dense (Gmsh
/// numbers nodes `1..=n`), a hash map once a tag lies far beyond the number of nodes.
#[derive(Debug, Default)]
pub(super) struct NodeIndex {
    /// The index of each tag (`usize::MAX`: none), while no tag is far out.
    dense: Vec<usize>,
    /// Every tag, once one is far out.
    sparse: Option<FastMap<u64, usize>>,
}

impl NodeIndex {
    /// Records node `tag` at `index` (the number of nodes recorded before); `false` if the tag
    /// is recorded already.
    fn insert(&mut self, tag: u64, index: usize) -> bool {
        // Dense while the vector stays within a few times the number of nodes.
        let limit = (index as u64).saturating_mul(4).saturating_add(1024);
        match usize::try_from(tag) {
            Ok(t) if self.sparse.is_none() && tag <= limit => {
                if t >= self.dense.len() {
                    let len = (t + 1).max(2 * self.dense.len());
                    self.dense.resize(len, usize::MAX);
                }
                let fresh = self.dense[t] == usize::MAX;
                if fresh {
                    self.dense[t] = index;
                }
                fresh
            }
            _ => {
                let dense = std::mem::take(&mut self.dense);
                let map = self.sparse.get_or_insert_with(|| {
                    (0u64..)
                        .zip(dense)
                        .filter(|&(_, i)| i != usize::MAX)
                        .collect()
                });
                map.insert(tag, index).is_none()
            }
        }
    }

    /// The index of node `tag`.
    pub(super) fn get(&self, tag: u64) -> Option<usize> {
        match &self.sparse {
            Some(map) => map.get(&tag).copied(),
            None => (usize::try_from(tag).ok())
                .and_then(|t| self.dense.get(t))
                .copied()
                .filter(|&i| i != usize::MAX),
        }
    }
}

/// Number of nodes of a Gmsh element type, and what it is; types the reader of `space` does not
/// read are errors.
fn element_kind(ty: usize, line: usize, space: Space) -> Result<(Kind, usize), GmshError> {
    let unsupported = |what: &str| {
        let reads = match space {
            Space::Planar => "3- and 6-node triangles with 2- or 3-node boundary lines and points",
            Space::Solid => "4- and 10-node tetrahedra with 3- or 6-node face triangles",
        };
        Err(GmshError::Unsupported(format!(
            "line {line}: element type {ty} ({what}); contactdd reads {reads}"
        )))
    };
    match (ty, space) {
        (15, _) => Ok((Kind::Point, 1)),
        (1, _) => Ok((Kind::Line, 2)),
        (8, _) => Ok((Kind::Line, 3)),
        (2, _) => Ok((Kind::Triangle(Order::P1), 3)),
        (9, _) => Ok((Kind::Triangle(Order::P2), 6)),
        (4, Space::Solid) => Ok((Kind::Tetrahedron(Order::P1), 4)),
        (11, Space::Solid) => Ok((Kind::Tetrahedron(Order::P2), 10)),
        (3 | 10 | 16, _) => unsupported("quadrilateral"),
        (4..=7 | 11..=14 | 17..=19, Space::Planar) => unsupported("3D element"),
        (29..=31, Space::Solid) => unsupported("higher-order tetrahedron"),
        (5..=7 | 12..=14 | 17..=19, Space::Solid) => {
            unsupported("3D element other than a tetrahedron")
        }
        (20..=25, _) => unsupported("higher-order or incomplete triangle"),
        (26..=28, _) => unsupported("higher-order line"),
        _ => unsupported("unknown or higher-order element"),
    }
}

/// Dimension of an element kind.
pub(super) fn kind_dim(kind: Kind) -> u8 {
    match kind {
        Kind::Point => 0,
        Kind::Line => 1,
        Kind::Triangle(_) => 2,
        Kind::Tetrahedron(_) => 3,
    }
}

/// Allocation size for `count` items announced by the file (not trusted for big allocations).
fn capacity(count: usize) -> usize {
    count.min(1 << 16)
}

impl RawMsh {
    /// Reads every section of the file `text`, for a mesh of `space`.
    pub(super) fn parse(text: &str, space: Space) -> Result<RawMsh, GmshError> {
        let mut tokens = Tokens::new(text);
        let mut raw = RawMsh {
            num_lines: tokens.num_lines(),
            ..RawMsh::default()
        };
        let mut format = None;
        let (mut seen_nodes, mut seen_elements) = (false, false);
        while let Some((line, token)) = tokens.next_opt() {
            let Some(version) = format else {
                format = Some(read_header(&mut tokens, line, token)?);
                continue;
            };
            let Some(name) = token.strip_prefix('$') else {
                return Err(tokens.error(
                    line,
                    format!(
                        "expected a section header such as $Nodes, found '{}'",
                        shown(token)
                    ),
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
                        Version::V4 => raw.read_elements_v4(&mut tokens, space)?,
                        Version::V2 => raw.read_elements_v2(&mut tokens, space)?,
                    }
                }
                _ if name.starts_with("End") => {
                    return Err(
                        tokens.error(line, format!("'{}' without its section", shown(token)))
                    );
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
        // The groups by name, so that each name is looked up once (a file may hold many).
        let mut by_name: HashMap<(u8, String), i64> = self
            .names
            .iter()
            .map(|(&(dim, tag), name)| ((dim, name.clone()), tag))
            .collect();
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
            if let Some(problem) = name_problem(name) {
                return Err(tokens.error(line, format!("physical name: {problem}")));
            }
            // Either would silently merge or drop groups: a boundary would not be what was drawn.
            if let Some(old) = self.names.get(&(dim, tag)) {
                return Err(tokens.error(
                    line,
                    format!(
                        "{dim}D physical group {tag} is named twice ('{}' and '{}')",
                        shown(old),
                        shown(name)
                    ),
                ));
            }
            if let Some(other) = by_name.get(&(dim, name.to_string())) {
                return Err(tokens.error(
                    line,
                    format!(
                        "physical name '{}' is used by two {dim}D groups ({other} and {tag}); \
                         give each group its own name",
                        shown(name)
                    ),
                ));
            }
            by_name.insert((dim, name.to_string()), tag);
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
        if !self.node_index.insert(tag, self.coords.len()) {
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
        // A node takes a tag and three coordinates: at least 8 bytes.
        self.coords.reserve(tokens.room_for(num_nodes, 8));
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
        self.coords.reserve(tokens.room_for(count, 8));
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

    /// Reads the `len` node tags of one element into `tags`, and returns where they start.
    fn read_element_nodes(
        &mut self,
        tokens: &mut Tokens<'_>,
        len: usize,
    ) -> Result<usize, GmshError> {
        let first = self.tags.len();
        for _ in 0..len {
            self.tags.push(tokens.parse("a node tag")?);
        }
        Ok(first)
    }

    /// The node tags of `element`.
    pub(super) fn nodes(&self, element: &RawElement) -> &[u64] {
        &self.tags[element.first_tag..element.first_tag + usize::from(element.num_nodes)]
    }

    fn read_elements_v4(&mut self, tokens: &mut Tokens<'_>, space: Space) -> Result<(), GmshError> {
        let num_blocks = tokens.usize("the number of element blocks")?;
        let (header, num_elements) = tokens.parse_at::<usize>("the number of elements")?;
        tokens.usize("the smallest element tag")?;
        tokens.usize("the largest element tag")?;
        // An element takes a tag and a node: at least 4 bytes.
        self.elements.reserve(tokens.room_for(num_elements, 4));
        let mut total = 0usize;
        for _ in 0..num_blocks {
            let dim = read_dim(tokens)?;
            let entity: i64 = tokens.parse("an entity tag")?;
            let (line, ty) = tokens.parse_at::<usize>("an element type")?;
            let count = tokens.usize("the number of elements in the block")?;
            if count == 0 {
                continue;
            }
            let (kind, len) = element_kind(ty, line, space)?;
            if kind_dim(kind) != dim {
                return Err(tokens.error(
                    line,
                    format!("element type {ty} in a block of dimension {dim}"),
                ));
            }
            // A node tag takes at least 2 bytes.
            (self.tags).reserve(tokens.room_for(count.saturating_mul(len), 2));
            for _ in 0..count {
                let (line, tag) = tokens.parse_at::<u64>("an element tag")?;
                let first_tag = self.read_element_nodes(tokens, len)?;
                self.elements.push(RawElement {
                    line,
                    tag,
                    kind,
                    first_tag,
                    // At most 10 (`element_kind`).
                    num_nodes: len as u8,
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

    fn read_elements_v2(&mut self, tokens: &mut Tokens<'_>, space: Space) -> Result<(), GmshError> {
        // An element takes a tag, a type, a tag count and a node: at least 8 bytes.
        let count = tokens.usize("the number of elements")?;
        self.elements.reserve(tokens.room_for(count, 8));
        // Most elements of a file are triangles: three node tags each, or more.
        (self.tags).reserve(tokens.room_for(count, 8).saturating_mul(3));
        for _ in 0..count {
            let (line, tag) = tokens.parse_at::<u64>("an element tag")?;
            let ty = tokens.usize("an element type")?;
            let (kind, len) = element_kind(ty, line, space)?;
            let num_tags = tokens.usize("the number of element tags")?;
            let mut physical = None;
            for k in 0..num_tags {
                let tag: i64 = tokens.parse("an element tag value")?;
                if k == 0 && tag != 0 {
                    physical = Some(tag);
                }
            }
            let first_tag = self.read_element_nodes(tokens, len)?;
            self.elements.push(RawElement {
                line,
                tag,
                kind,
                first_tag,
                // At most 10 (`element_kind`).
                num_nodes: len as u8,
                entity: None,
                physical,
            });
        }
        Ok(())
    }

    /// Physical tags of an element.
    pub(super) fn physicals<'a>(&'a self, element: &'a RawElement) -> &'a [i64] {
        if let Some(tag) = &element.physical {
            return std::slice::from_ref(tag);
        }
        element
            .entity
            .and_then(|key| self.entities.get(&key))
            .map_or(&[], Vec::as_slice)
    }

    /// Name of physical group `tag` of dimension `dim`.
    pub(super) fn group_name(&self, dim: u8, tag: i64) -> String {
        self.names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| tag.to_string())
    }
}

/// Reads the `$MeshFormat` section that every file opens with (`token` at `line`: its header).
fn read_header(tokens: &mut Tokens<'_>, line: usize, token: &str) -> Result<Version, GmshError> {
    if token != "$MeshFormat" {
        return Err(tokens.error(
            line,
            format!(
                "not a Gmsh mesh: expected $MeshFormat, found '{}'",
                shown(token)
            ),
        ));
    }
    tokens.section = "MeshFormat";
    let version = read_format(tokens)?;
    tokens.expect_end()?;
    Ok(version)
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
                "line {line}: MSH format version {}; save the mesh as version 4.1 or 2.2 \
                 ASCII (gmsh -format msh41)",
                shown(other)
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
                format!("expected file type 0 (ASCII), found '{}'", shown(other)),
            ))
        }
    }
    tokens.usize("the data size")?;
    Ok(version)
}
