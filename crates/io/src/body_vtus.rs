//! The `.vtu` file of each body of a result: its nodal fields (displacement, stress, principal
//! stresses, von Mises, σ_n of the contact nodes), with the model and the pairs' results the contact
//! pressure, the contact point data and the element von Mises. File names are the [`safe_file_name`]s of the body names, made unique.

use rayon::prelude::*;
use std::collections::HashSet;
use std::io::{Error, ErrorKind};
use std::path::{Path, PathBuf};

use contactdd_core::Mesh;
use contactdd_ddm::solution::{BodyResult, PairResult};
use contactdd_ddm::Model;

use crate::atomic::{write_atomic, write_staged};
use crate::fields::{
    contact_point_data, contact_pressures, element_von_mises, friction_point_data, has_friction,
    nodal_contact_pressure, principal, tensor, ContactPointData,
};
use crate::result_set::ResultSet;
use crate::vtu::{
    vtu_bytes, vtu_pieces_bytes, Field, VtuData, VtuFormat, VtuLayout, VtuOptions, COLLECTION_STEM,
};

/// Writes `<body>.vtu` per body into `dir` with the nodal fields of the results alone:
/// `displacement` (vector), `stress` (3×3 tensor), `principal_stress_1` ≥ `_2` ≥ `_3`,
/// `sigma_xx`, `sigma_yy`, `sigma_xy`, `sigma_zz`, `von_mises` and `sigma_n` (scalars, which
/// ParaView colours by directly; `sigma_n` is [`BodyResult::contact_pressure`], ≤ 0). File names
/// are [`safe_file_name`]s of the body names, made unique. [`write_solution_vtus`] adds the
/// contact pressure p ≥ 0, the contact point data and the element von Mises. The files are in
/// the default [`VtuFormat`].
pub fn write_body_vtus(dir: &Path, bodies: &[BodyResult]) -> std::io::Result<Vec<PathBuf>> {
    let mut written = Vec::with_capacity(bodies.len());
    let all = |_| true;
    // Not in a result set: each file synced on its own.
    write_vtus(
        (dir, "", VtuFormat::default(), write_atomic),
        bodies,
        &all,
        |_, _| Ok(Extra::default()),
        &mut written,
    )?;
    Ok(written)
}

/// [`write_body_vtus`] into a result set, plus, from the model and the pairs' results, the point
/// data `contact_pressure` (p ≥ 0 of [`nodal_contact_pressure`], 0 off the contact points), `gap`
/// and `contact_status` (1 closed, 0 open, −1 no partner; both NaN off the contact points), when
/// some pair has friction `contact_tangential` (σ_t) and `friction_status` (0 open, 1 stick,
/// 2 slip; both 0 off the contact points), and the cell data `element_von_mises` (at each
/// element's centroid). `bodies` are in the
/// order of `model.bodies`. Each file joins the set as soon as it is written, so that a failure
/// part way removes it with the set ([`ResultSet::abandon`]). The files are in the default
/// [`VtuFormat`].
pub fn write_solution_vtus(
    set: &mut ResultSet,
    model: &Model,
    bodies: &[BodyResult],
    contact: &[PairResult],
) -> std::io::Result<()> {
    write_solution_vtus_as(set, model, bodies, contact, "", VtuFormat::default())
}

/// [`write_solution_vtus`] with `suffix` after each body's file name (`<body><suffix>.vtu`, e.g.
/// the `-step3` of a load step), in the encoding and layout of `vtu` (a [`VtuFormat`] alone
/// keeps one file per body; with [`VtuLayout::Collection`] every body goes into the one file
/// `bodies<suffix>.vtu`).
pub fn write_solution_vtus_as(
    set: &mut ResultSet,
    model: &Model,
    bodies: &[BodyResult],
    contact: &[PairResult],
    suffix: &str,
    vtu: impl Into<VtuOptions>,
) -> std::io::Result<()> {
    let vtu = vtu.into();
    let mut written = Vec::with_capacity(bodies.len());
    let dir = set.dir().to_path_buf();
    let to = (dir.as_path(), suffix, vtu.format);
    let result = match vtu.layout {
        VtuLayout::PerBody => {
            write_solution_vtus_of(to, model, (bodies, contact), &|_| true, &mut written)
        }
        VtuLayout::Collection => {
            write_solution_collection(to, model, (bodies, contact), &mut written)
        }
    };
    set.record(written);
    result
}

/// [`write_solution_vtus_as`] into `dir` (with `suffix` and `format`: `to`) for the bodies
/// `owns` selects only (a process of a distributed solve writes its own); each path joins
/// `written` once its file is there. The file names are those of all bodies: the same as when
/// one process writes them all.
pub(crate) fn write_solution_vtus_of(
    to: (&Path, &str, VtuFormat),
    model: &Model,
    (bodies, contact): (&[BodyResult], &[PairResult]),
    owns: &dyn Fn(usize) -> bool,
    written: &mut Vec<PathBuf>,
) -> std::io::Result<()> {
    let pressures = contact_pressures(contact, bodies);
    let friction = has_friction(model);
    let (dir, suffix, format) = to;
    // A result set syncs its files together before its summary claims them.
    write_vtus(
        (dir, suffix, format, write_staged),
        bodies,
        owns,
        |b, body| solution_extra(model, (contact, &pressures, friction), b, body),
        written,
    )
}

/// Writes the [`VtuLayout::Collection`] file of one result into `dir` (with `suffix` and
/// `format`: `to`): [`collection_path`], one `Piece` per body in body order, each with the arrays
/// of the body's file of [`write_solution_vtus_of`]; its path joins `written` once it is there.
pub(crate) fn write_solution_collection(
    to: (&Path, &str, VtuFormat),
    model: &Model,
    (bodies, contact): (&[BodyResult], &[PairResult]),
    written: &mut Vec<PathBuf>,
) -> std::io::Result<()> {
    let pressures = contact_pressures(contact, bodies);
    let friction = has_friction(model);
    let (dir, suffix, format) = to;
    // The bodies' arrays are independent: computed in parallel, written in body order.
    let arrays = (bodies.par_iter().enumerate())
        .map(|(b, body)| {
            let extra = solution_extra(model, (contact, &pressures, friction), b, body)?;
            Ok(BodyArrays::new(body, extra))
        })
        .collect::<std::io::Result<Vec<BodyArrays>>>()?;
    let fields: Vec<_> = (arrays.iter().zip(bodies))
        .map(|(a, body)| a.fields(body))
        .collect();
    let pieces: Vec<(&Mesh, VtuData<'_>)> = (bodies.iter().zip(&fields))
        .map(|(body, (points, cells))| (&body.mesh, body_data(body, points, cells)))
        .collect();
    let bytes = vtu_pieces_bytes(&pieces, format)?;
    let path = collection_path(dir, suffix);
    write_staged(&path, &bytes)?;
    written.push(path);
    Ok(())
}

/// The path of the [`VtuLayout::Collection`] file of a result in `dir`:
/// `<COLLECTION_STEM><suffix>.vtu` ([`COLLECTION_STEM`]).
pub(crate) fn collection_path(dir: &Path, suffix: &str) -> PathBuf {
    dir.join(format!("{COLLECTION_STEM}{suffix}.vtu"))
}

/// The [`Extra`] arrays of body `b` of a solution, from the model and the pairs' results
/// (`contact`, their contact `pressures` and whether some pair has `friction`).
fn solution_extra(
    model: &Model,
    (contact, pressures, friction): (&[PairResult], &[Vec<f64>], bool),
    b: usize,
    body: &BodyResult,
) -> std::io::Result<Extra> {
    let elastic = model.bodies.get(b).ok_or_else(|| {
        Error::new(
            ErrorKind::InvalidInput,
            "more body results than model bodies",
        )
    })?;
    let nodes = body.mesh.num_nodes();
    Ok(Extra {
        pressure: Some(nodal_contact_pressure(
            &body.name, nodes, contact, pressures,
        )),
        contact: Some(contact_point_data(&body.name, nodes, contact)),
        element_von_mises: Some(element_von_mises(elastic, &body.displacement)),
        friction: friction.then(|| friction_point_data(&body.name, nodes, contact)),
    })
}

/// The fields of a body's `.vtu` that need more than its [`BodyResult`].
#[derive(Default)]
struct Extra {
    pressure: Option<Vec<f64>>,
    contact: Option<ContactPointData>,
    element_von_mises: Option<Vec<f64>>,
    /// σ_t and the friction status code per node.
    friction: Option<(Vec<f64>, Vec<f64>)>,
}

/// The `.vtu` path of each body: `<name><suffix>.vtu`, or `<name>-<b><suffix>.vtu` when an
/// earlier body's name gives the same file name.
pub(crate) fn vtu_paths(dir: &Path, suffix: &str, bodies: &[BodyResult]) -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = Vec::with_capacity(bodies.len());
    // The names taken so far (a set: thousands of bodies are compared in linear time).
    let mut taken: HashSet<PathBuf> = HashSet::with_capacity(bodies.len());
    for (b, body) in bodies.iter().enumerate() {
        let name = safe_file_name(&body.name);
        let mut path = dir.join(format!("{name}{suffix}.vtu"));
        if taken.contains(&path) {
            path = dir.join(format!("{name}-{b}{suffix}.vtu"));
        }
        taken.insert(path.clone());
        paths.push(path);
    }
    paths
}

/// How a `.vtu` file's bytes reach its path: [`write_atomic`] or [`write_staged`].
type Writer = fn(&Path, &[u8]) -> std::io::Result<()>;

/// Writes the `.vtu` of each body that `owns` selects into `dir` (file names with `suffix`, in
/// `format`, by `write`), pushing each path to `written` once the file is there.
fn write_vtus(
    (dir, suffix, format, write): (&Path, &str, VtuFormat, Writer),
    bodies: &[BodyResult],
    owns: &dyn Fn(usize) -> bool,
    extra: impl Fn(usize, &BodyResult) -> std::io::Result<Extra> + Sync,
    written: &mut Vec<PathBuf>,
) -> std::io::Result<()> {
    let paths = vtu_paths(dir, suffix, bodies);
    let mine: Vec<(usize, PathBuf)> = (paths.into_iter().enumerate())
        .filter(|&(b, _)| owns(b))
        .collect();
    // The bodies' files are independent: written in parallel, listed in body order.
    let results: Vec<std::io::Result<()>> = mine
        .par_iter()
        .map(|(b, path)| {
            let bytes = body_vtu(&bodies[*b], extra(*b, &bodies[*b])?, format)?;
            write(path, &bytes)
        })
        .collect();
    let mut first_error = None;
    for ((_, path), result) in mine.into_iter().zip(results) {
        match result {
            Ok(()) => written.push(path),
            Err(e) => first_error = first_error.or(Some(e)),
        }
    }
    first_error.map_or(Ok(()), Err)
}

/// The bytes of one body's `.vtu` with its fields and `extra`.
fn body_vtu(body: &BodyResult, extra: Extra, format: VtuFormat) -> std::io::Result<Vec<u8>> {
    let arrays = BodyArrays::new(body, extra);
    let (points, cells) = arrays.fields(body);
    vtu_bytes(&body.mesh, body_data(body, &points, &cells), format)
}

/// The arrays of a body's `.vtu`: the displacement and `points` per node, `cells` per cell.
fn body_data<'a>(
    body: &'a BodyResult,
    points: &'a [Field<'a>],
    cells: &'a [Field<'a>],
) -> VtuData<'a> {
    VtuData {
        displacement: Some(&body.displacement),
        points,
        cells,
    }
}

/// The arrays of a body's `.vtu` computed from its [`BodyResult`], with its [`Extra`] ones.
struct BodyArrays {
    tensors: Vec<f64>,
    /// The principal stresses, largest first.
    principals: [Vec<f64>; 3],
    /// σ_xx, σ_yy, σ_xy, σ_zz.
    components: [Vec<f64>; 4],
    extra: Extra,
}

impl BodyArrays {
    fn new(body: &BodyResult, extra: Extra) -> BodyArrays {
        let component = |k: usize| body.stress.iter().map(|s| s[k]).collect::<Vec<f64>>();
        let principals: Vec<[f64; 3]> = body.stress.iter().map(principal).collect();
        let principal_k = |k: usize| principals.iter().map(|p| p[k]).collect::<Vec<f64>>();
        BodyArrays {
            tensors: body.stress.iter().flat_map(tensor).collect(),
            principals: [principal_k(0), principal_k(1), principal_k(2)],
            components: [component(0), component(1), component(2), component(3)],
            extra,
        }
    }

    /// The point fields and the cell fields of the file of `body`, in file order.
    fn fields<'a>(&'a self, body: &'a BodyResult) -> (Vec<Field<'a>>, Vec<Field<'a>>) {
        let field = |name, components, values| Field {
            name,
            components,
            values,
        };
        let [p1, p2, p3] = &self.principals;
        let [sxx, syy, sxy, szz] = &self.components;
        let mut points = vec![
            field("stress", 9, &self.tensors),
            field("principal_stress_1", 1, p1),
            field("principal_stress_2", 1, p2),
            field("principal_stress_3", 1, p3),
            field("sigma_xx", 1, sxx),
            field("sigma_yy", 1, syy),
            field("sigma_xy", 1, sxy),
            field("sigma_zz", 1, szz),
            field("von_mises", 1, &body.von_mises),
            field("sigma_n", 1, &body.contact_pressure),
        ];
        let extra = &self.extra;
        if let Some(p) = &extra.pressure {
            points.push(field("contact_pressure", 1, p));
        }
        if let Some(c) = &extra.contact {
            points.push(field("gap", 1, &c.gap));
            points.push(field("contact_status", 1, &c.status));
        }
        if let Some((tangential, status)) = &extra.friction {
            points.push(field("contact_tangential", 1, tangential));
            points.push(field("friction_status", 1, status));
        }
        let cells: Vec<Field<'_>> = (extra.element_von_mises.as_deref())
            .map(|v| field("element_von_mises", 1, v))
            .into_iter()
            .collect();
        (points, cells)
    }
}

/// A name usable as a file name on every platform: letters, digits, `-`, `_` and `.` are kept,
/// anything else becomes `_` (an empty name becomes `_`).
pub fn safe_file_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.chars().all(|c| c == '.') {
        "_".into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bodies whose names give the same file name get the body's index appended, in order.
    #[test]
    fn vtu_names_that_collide_get_the_body_index() {
        let mesh = contactdd_core::Mesh::new(
            vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            contactdd_core::Order::P1,
            vec![0, 1, 2],
            Default::default(),
            Default::default(),
        )
        .unwrap();
        let body = |name: &str| BodyResult {
            name: name.to_string(),
            mesh: mesh.clone(),
            displacement: Vec::new(),
            stress: Vec::new(),
            von_mises: Vec::new(),
            contact_pressure: Vec::new(),
            node_ids: Vec::new(),
        };
        let bodies = ["a b", "c", "a_b", "a/b"].map(body);
        let names: Vec<String> = vtu_paths(Path::new("out"), "", &bodies)
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["a_b.vtu", "c.vtu", "a_b-2.vtu", "a_b-3.vtu"]);
    }

    #[test]
    fn file_names_are_sanitised() {
        assert_eq!(safe_file_name("lower"), "lower");
        assert_eq!(safe_file_name("a/b c"), "a_b_c");
        assert_eq!(safe_file_name(".."), "_");
        assert_eq!(safe_file_name(""), "_");
    }
}
