//! The mesh assembled from a file's raw content: the body's triangles chosen, nodes renumbered,
//! elements sorted into cells, boundaries and node sets.

use std::collections::{BTreeMap, BTreeSet};

use crate::error::{GmshError, MeshError};
use crate::fast_hash::hash_of;
use crate::geometry::{Point, DIM};
use crate::mesh::{counter_clockwise, dist, Edge, Mesh, Order};
use crate::names::{listed, shown};

use super::raw::{kind_dim, Few, Kind, RawElement, RawMsh};

/// The sorted positions of a triangle's vertices, as bits ([`RawMsh::vertex_key`]).
type VertexKey = [[u64; 2]; 3];

impl RawMsh {
    /// Assembles and validates the mesh: the triangles' order and nodes, the nodes renumbered,
    /// the elements sorted into cells, boundaries and node sets, then [`Mesh::new`].
    pub(super) fn build(self, surface: Option<&str>) -> Result<Mesh, GmshError> {
        self.check_names_used()?;
        let body = self.surface_tag(surface)?;
        let (order, used) = self.triangle_order_and_nodes(body)?;
        let (nodes, new_index) = self.renumber_nodes(&used)?;
        let (cells, boundaries, node_sets) = self.sort_elements(order, &nodes, &new_index, body)?;
        Mesh::new(nodes, order, cells, boundaries, node_sets).map_err(|e| match e {
            // Name the file line of a folded curved triangle.
            MeshError::CurvedInverted { element } => GmshError::Unsupported(format!(
                "line {}: {}",
                self.triangle_line(element, body),
                MeshError::CurvedInverted { element }
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
            format!(
                "physical surfaces: {}",
                listed(names.iter().map(String::as_str)).join(", ")
            )
        };
        match surface {
            Some(name) => match tags.iter().find(|&&t| self.group_name(2, t) == name) {
                Some(&tag) => Ok(Some(tag)),
                None => Err(GmshError::Surface(format!(
                    "no physical surface named '{}' ({listed})",
                    shown(name)
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
    pub(super) fn check_names_used(&self) -> Result<(), GmshError> {
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
    pub(super) fn node_position(&self, element: &RawElement, tag: u64) -> Result<usize, GmshError> {
        self.node_index.get(tag).ok_or_else(|| GmshError::Parse {
            line: element.line,
            message: format!("element refers to node {tag}, which is not in $Nodes"),
        })
    }

    /// Whether every node of `element` is a node of the body (`new_index` is set).
    fn touches(&self, element: &RawElement, new_index: &[usize]) -> bool {
        self.nodes(element).iter().all(|&tag| {
            self.node_index
                .get(tag)
                .and_then(|i| new_index.get(i))
                .is_some_and(|&n| n != usize::MAX)
        })
    }

    /// The nodes of `element` in the new numbering `new_index`; a node of no triangle is an
    /// error.
    fn new_ids(&self, element: &RawElement, new_index: &[usize]) -> Result<Few<usize>, GmshError> {
        let mut ids = Few::new();
        for &tag in self.nodes(element).iter() {
            let i = self.node_position(element, tag)?;
            let id = new_index.get(i).copied().filter(|&n| n != usize::MAX);
            ids.push(id.ok_or_else(|| GmshError::Parse {
                line: element.line,
                message: format!(
                    "element refers to node {tag}, which is not a node of any triangle"
                ),
            })?);
        }
        Ok(ids)
    }

    /// The positions of the first three nodes (a triangle's vertices) of `element`, sorted, as
    /// bits (`-0.0` as `0.0`): equal for two triangles on the same three points.
    fn vertex_key(&self, element: &RawElement) -> Result<VertexKey, GmshError> {
        let mut key = [[0; 2]; 3];
        for (k, &tag) in key.iter_mut().zip(self.nodes(element).iter()) {
            let xyz = self.coords[self.node_position(element, tag)?];
            *k = [(xyz[0] + 0.0).to_bits(), (xyz[1] + 0.0).to_bits()];
        }
        key.sort_unstable();
        Ok(key)
    }

    /// The order of the triangles (all the same) and, per node of `coords`, whether a triangle
    /// uses it.
    fn triangle_order_and_nodes(&self, body: Option<i64>) -> Result<(Order, Vec<bool>), GmshError> {
        let mut order = None;
        let mut used = vec![false; self.coords.len()];
        // A triangle listed twice would be assembled twice: a body twice as stiff there. Its
        // vertices are compared by position, so that a copy on duplicated nodes is caught too:
        // the hashes of their keys are sorted after the pass (less memory than a hash map).
        let mut keys: Vec<(u64, usize)> = Vec::new();
        // The first error of the pass: (element, 0 before its duplicate check or 2 after, error).
        let mut failure = None;
        for (index, element) in self.elements.iter().enumerate() {
            let Kind::Triangle(o) = element.kind else {
                continue;
            };
            if !self.in_body(element, body) {
                continue;
            }
            match self.vertex_key(element) {
                Ok(key) => keys.push((hash_of(&key), index)),
                Err(e) => {
                    failure = Some((index, 0, e));
                    break;
                }
            }
            if let Err(e) = self.check_triangle(element, o, &mut order, &mut used) {
                failure = Some((index, 2, e));
                break;
            }
        }
        if let Some((first, second)) = self.first_duplicate(&mut keys) {
            // The error the file shows first: a duplicate comes after the vertices of its own
            // triangle are found and before the rest of its checks.
            if failure
                .as_ref()
                .map_or(true, |&(index, stage, _)| (second, 1) < (index, stage))
            {
                let (first, second) = (&self.elements[first], &self.elements[second]);
                return Err(GmshError::Parse {
                    line: second.line,
                    message: format!(
                        "triangles {} (line {}) and {} have the same three vertices; \
                         a mesh lists each triangle once",
                        first.tag, first.line, second.tag
                    ),
                });
            }
        }
        if let Some((_, _, e)) = failure {
            return Err(e);
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

    /// Checks that triangle `element` of order `o` has the order of those before (`order`, set
    /// by the first) and nodes in `$Nodes`, and marks them `used`.
    fn check_triangle(
        &self,
        element: &RawElement,
        o: Order,
        order: &mut Option<Order>,
        used: &mut [bool],
    ) -> Result<(), GmshError> {
        match *order {
            None => *order = Some(o),
            Some(first) if first != o => {
                return Err(GmshError::Unsupported(format!(
                    "line {}: the mesh mixes 3-node and 6-node triangles",
                    element.line
                )));
            }
            Some(_) => {}
        }
        for &tag in self.nodes(element).iter() {
            let i = self.node_position(element, tag)?;
            if let Some(u) = used.get_mut(i) {
                *u = true;
            }
        }
        Ok(())
    }

    /// The first triangle in file order whose vertex key an earlier one has: (the earlier one,
    /// it), as indices of the elements. `keys` holds (the hash of its vertex key, element) per
    /// triangle, and is sorted; triangles of equal hashes are compared by their keys.
    fn first_duplicate(&self, keys: &mut [(u64, usize)]) -> Option<(usize, usize)> {
        keys.sort_unstable();
        let mut found: Option<(usize, usize)> = None;
        for run in keys.chunk_by(|a, b| a.0 == b.0).filter(|run| run.len() > 1) {
            // The vertex keys were read once already: they cannot fail here.
            let mut exact: Vec<(VertexKey, usize)> = (run.iter())
                .filter_map(|&(_, e)| Some((self.vertex_key(&self.elements[e]).ok()?, e)))
                .collect();
            exact.sort_unstable();
            // Equal keys are sorted by element: the first two of a run meet first.
            let pairs = exact.windows(2).filter(|w| w[0].0 == w[1].0);
            for pair in pairs.map(|w| (w[0].1, w[1].1)) {
                if found.map_or(true, |(_, second)| pair.1 < second) {
                    found = Some(pair);
                }
            }
        }
        found
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
            let ids = self.new_ids(element, new_index)?;
            match (element.kind, &*ids) {
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
