//! The tetrahedral mesh assembled from a file's raw content: the body's tetrahedra chosen, their
//! nodes renumbered, the physical surfaces' triangles sorted into named faces, then
//! [`SolidMesh::new`].

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use crate::error::GmshError;
use crate::mesh::Order;
use crate::names::{listed, shown};
use crate::solid::element::TET_EDGES;
use crate::solid::{cross, dot3, sub, Point3, SolidError, SolidMesh, TetOrder};

use super::raw::{Few, Kind, RawElement, RawMsh};

/// The node permutation that swaps vertices 1 and 2 of a 10-node tetrahedron (Gmsh's order),
/// turning a negative volume positive; its first four entries do it for a 4-node one.
const SWAP_1_2: [usize; 10] = [0, 2, 1, 3, 6, 5, 4, 7, 9, 8];

/// The local vertices of each face of a tetrahedron.
const TET_FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]];

/// Sorted vertices of a face → (number of the body's tetrahedra with this face, the last one).
type FaceOwners = HashMap<[usize; 3], (usize, usize)>;

/// The tetrahedra of the body, renumbered.
struct Body {
    order: TetOrder,
    nodes: Vec<Point3>,
    /// Per node of the file (index into `coords`), its new index (`usize::MAX`: not in the body).
    new_index: Vec<usize>,
    /// Flat connectivity, positively oriented.
    tets: Vec<usize>,
    /// The file line of each tetrahedron.
    lines: Vec<usize>,
}

impl RawMsh {
    /// Assembles and validates the tetrahedral mesh of physical volume `volume` (`None`: all
    /// tetrahedra of a file with at most one physical volume).
    pub(super) fn build_solid(self, volume: Option<&str>) -> Result<SolidMesh, GmshError> {
        self.check_names_used()?;
        let chosen = self.volume_tag(volume)?;
        let body = self.body(chosen)?;
        let faces = self.faces(&body, chosen.is_some())?;
        let Body {
            order,
            nodes,
            tets,
            lines,
            ..
        } = body;
        SolidMesh::new(nodes, order, tets, faces).map_err(|e| {
            let element = match e {
                SolidError::DegenerateElement { element }
                | SolidError::InvertedElement { element }
                | SolidError::CurvedInverted { element }
                | SolidError::NodeOutOfRange { element, .. } => Some(element),
                _ => None,
            };
            GmshError::Solid {
                line: element.and_then(|k| lines.get(k).copied()),
                source: Box::new(e),
            }
        })
    }

    /// The physical volume whose tetrahedra make the body: the one named `volume`, or `None`
    /// (every tetrahedron) when no volume is named and the file has at most one physical volume.
    fn volume_tag(&self, volume: Option<&str>) -> Result<Option<i64>, GmshError> {
        let tags: BTreeSet<i64> = (self.elements.iter())
            .filter(|e| matches!(e.kind, Kind::Tetrahedron(_)))
            .flat_map(|e| self.physicals(e).iter().copied())
            .collect();
        let names: Vec<String> = tags.iter().map(|&t| self.group_name(3, t)).collect();
        let listed = if names.is_empty() {
            "the file has no physical volume".to_string()
        } else {
            format!(
                "physical volumes: {}",
                listed(names.iter().map(String::as_str)).join(", ")
            )
        };
        match volume {
            Some(name) => match tags.iter().find(|&&t| self.group_name(3, t) == name) {
                Some(&tag) => Ok(Some(tag)),
                None => Err(GmshError::Volume(format!(
                    "no physical volume named '{}' ({listed})",
                    shown(name)
                ))),
            },
            None if tags.len() > 1 => Err(GmshError::Volume(format!(
                "the file holds {} bodies ({listed}); name the body's physical volume",
                tags.len()
            ))),
            None => Ok(None),
        }
    }

    /// The tetrahedra of physical volume `chosen` (`None`: all), of one order, their nodes
    /// renumbered in file order and each positively oriented.
    fn body(&self, chosen: Option<i64>) -> Result<Body, GmshError> {
        let selected: Vec<(&RawElement, Order)> = (self.elements.iter())
            .filter_map(|e| match e.kind {
                Kind::Tetrahedron(o) => Some((e, o)),
                _ => None,
            })
            .filter(|(e, _)| chosen.map_or(true, |tag| self.physicals(e).contains(&tag)))
            .collect();
        let Some(&(first, first_order)) = selected.first() else {
            return Err(GmshError::NoTetrahedra);
        };
        let mut used = vec![false; self.coords.len()];
        for &(element, o) in &selected {
            if o != first_order {
                return Err(GmshError::MixedTetrahedra {
                    line: element.line,
                    tag: element.tag,
                    nodes: usize::from(element.num_nodes),
                    first_line: first.line,
                    first_nodes: usize::from(first.num_nodes),
                });
            }
            for &tag in self.nodes(element).iter() {
                used[self.node_position(element, tag)?] = true;
            }
        }
        let mut new_index = vec![usize::MAX; self.coords.len()];
        let mut nodes = Vec::new();
        for ((&xyz, &u), slot) in self.coords.iter().zip(&used).zip(&mut new_index) {
            if u {
                *slot = nodes.len();
                nodes.push(xyz);
            }
        }
        let order = match first_order {
            Order::P1 => TetOrder::P1,
            Order::P2 => TetOrder::P2,
        };
        let mut body = Body {
            order,
            nodes,
            new_index,
            tets: Vec::with_capacity(selected.len() * order.nodes_per_tet()),
            lines: Vec::with_capacity(selected.len()),
        };
        let mut seen: HashMap<[usize; 4], &RawElement> = HashMap::with_capacity(selected.len());
        for &(element, _) in &selected {
            // Every node of a chosen tetrahedron is a node of the body.
            let ids: Vec<usize> = (self.body_ids(element, &body.new_index)?.iter())
                .flatten()
                .copied()
                .collect();
            let mut vertices = [ids[0], ids[1], ids[2], ids[3]];
            vertices.sort_unstable();
            if let Some(earlier) = seen.insert(vertices, element) {
                return Err(GmshError::Parse {
                    line: element.line,
                    message: format!(
                        "tetrahedra {} (line {}) and {} have the same four vertices; a mesh \
                         lists each tetrahedron once",
                        earlier.tag, earlier.line, element.tag
                    ),
                });
            }
            body.push(&ids, element.line);
        }
        Ok(body)
    }

    /// The nodes of `element` in the body's numbering `new_index`; `None` for a node outside
    /// the body.
    fn body_ids(
        &self,
        element: &RawElement,
        new_index: &[usize],
    ) -> Result<Few<Option<usize>>, GmshError> {
        let mut ids = Few::new();
        for &tag in self.nodes(element).iter() {
            let i = self.node_position(element, tag)?;
            ids.push(new_index.get(i).copied().filter(|&n| n != usize::MAX));
        }
        Ok(ids)
    }

    /// The named faces: the triangles of every physical surface that are boundary faces of the
    /// body. With a chosen volume (`selected`), triangles that are no face of its tetrahedra
    /// belong to another body and are left out; without, they are errors.
    fn faces(&self, body: &Body, selected: bool) -> Result<Vec<(String, Vec<usize>)>, GmshError> {
        let owners = body.face_owners();
        let mut faces: BTreeMap<String, Vec<usize>> = BTreeMap::new();
        let mut seen: HashSet<(i64, [usize; 3])> = HashSet::new();
        for element in &self.elements {
            if !matches!(element.kind, Kind::Triangle(_)) {
                continue;
            }
            let groups = self.physicals(element);
            let Some(&group) = groups.first() else {
                continue;
            };
            let not_a_face = |reason: &str| GmshError::NotABoundaryFace {
                line: element.line,
                tag: element.tag,
                group: self.group_name(2, group),
                reason: reason.to_string(),
            };
            let ids = self.body_ids(element, &body.new_index)?;
            let Some(vertices) = ids[..3].iter().copied().collect::<Option<Vec<usize>>>() else {
                if selected {
                    continue;
                }
                return Err(not_a_face("a vertex of it is a node of no tetrahedron"));
            };
            let key = sorted3(&vertices);
            let owner = owners.get(&key).copied();
            if selected && owner.is_none() {
                continue;
            }
            if ids.len() != body.order.nodes_per_face() {
                return Err(GmshError::FaceOrder {
                    line: element.line,
                    tag: element.tag,
                    group: self.group_name(2, group),
                    nodes: ids.len(),
                    tet_nodes: body.order.nodes_per_tet(),
                });
            }
            // A mid-edge node outside the body cannot be its tetrahedron's.
            let ids: Vec<usize> = ids.iter().map(|id| id.unwrap_or(usize::MAX)).collect();
            match owner {
                None => return Err(not_a_face("no tetrahedron has it as a face")),
                Some((count, _)) if count > 1 => {
                    return Err(not_a_face(
                        "two tetrahedra share it, so it lies inside the body",
                    ))
                }
                Some((_, tet)) if !body.same_mid_nodes(&ids, tet) => {
                    return Err(not_a_face(
                        "its mid-edge nodes are not those of its tetrahedron's edges",
                    ))
                }
                Some(_) => {}
            }
            for &tag in groups {
                if !seen.insert((tag, key)) {
                    return Err(GmshError::Parse {
                        line: element.line,
                        message: format!(
                            "triangle {} is listed twice in physical surface '{}'",
                            element.tag,
                            self.group_name(2, tag)
                        ),
                    });
                }
                (faces.entry(self.group_name(2, tag)).or_default()).extend_from_slice(&ids);
            }
        }
        Ok(faces.into_iter().collect())
    }
}

impl Body {
    /// Appends the tetrahedron of nodes `ids` (all in the body) read at `line`, reoriented to a
    /// positive volume if needed.
    fn push(&mut self, ids: &[usize], line: usize) {
        let p = |i: usize| self.nodes.get(ids[i]).copied().unwrap_or_default();
        let det = dot3(sub(p(1), p(0)), cross(sub(p(2), p(0)), sub(p(3), p(0))));
        if det < 0.0 {
            self.tets
                .extend(SWAP_1_2[..ids.len()].iter().map(|&k| ids[k]));
        } else {
            self.tets.extend_from_slice(ids);
        }
        self.lines.push(line);
    }

    /// The tetrahedra of each face of the body.
    fn face_owners(&self) -> FaceOwners {
        let npt = self.order.nodes_per_tet();
        let mut owners = FaceOwners::with_capacity(2 * self.lines.len());
        for (e, c) in self.tets.chunks(npt).enumerate() {
            for f in TET_FACES {
                let owner = owners
                    .entry(sorted3(&[c[f[0]], c[f[1]], c[f[2]]]))
                    .or_insert((0, e));
                *owner = (owner.0 + 1, e);
            }
        }
        owners
    }

    /// Whether the mid-edge nodes of the 6-node triangle `tri` are those of tetrahedron `e`
    /// (always true for a 3-node triangle).
    fn same_mid_nodes(&self, tri: &[usize], e: usize) -> bool {
        if tri.len() == 3 {
            return true;
        }
        let npt = self.order.nodes_per_tet();
        let c = &self.tets[e * npt..(e + 1) * npt];
        let mid = |a: usize, b: usize| {
            TET_EDGES.iter().enumerate().find_map(|(k, &[i, j])| {
                let (vi, vj) = (c[i], c[j]);
                ((vi == a && vj == b) || (vi == b && vj == a)).then_some(c[4 + k])
            })
        };
        [(0, 1, 3), (1, 2, 4), (2, 0, 5)]
            .iter()
            .all(|&(i, j, m)| mid(tri[i], tri[j]) == Some(tri[m]))
    }
}

/// The sorted first three entries (a triangle's vertices) of `ids`.
fn sorted3(ids: &[usize]) -> [usize; 3] {
    let mut k = [ids[0], ids[1], ids[2]];
    k.sort_unstable();
    k
}
