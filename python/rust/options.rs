//! The solver options of the Python API (the keyword arguments of `solve`, `solve_steps`,
//! `sweep` and `Problem.solver`: the keys of a `[solver]` table in snake_case), checked as a
//! `[solver]` table is, and γ between Python and Rust.

use pyo3::prelude::*;

use contactdd_ddm::{
    Condensation, Enforcement, Friction, Gamma, Method, Model, Settings, SetupError,
};
use contactdd_io::pairs::{friction_law, parse_friction};
use contactdd_io::problem::{
    AcceleratorSpec, CoarseSpec, EnforcementSpec, FrictionSpec, GammaSpec, SolverSpec,
};
use contactdd_io::setup;

use crate::convert::from_name;
use crate::error::setup_error;
use crate::schema::parse;

/// A relaxation parameter as given from Python: a number or `"auto"`.
#[derive(FromPyObject, Clone, Debug)]
pub enum GammaArg {
    /// A constant γ.
    Value(f64),
    /// A rule name (`"auto"`).
    Name(String),
}

/// The solver options of the Python API, one field per keyword (the names of a `[solver]`
/// table, and `enforcement`); `None` keeps the problem's value. `solve`, `solve_steps`, `sweep`
/// and `Problem.solver` each take the subset their Python signature lists.
#[derive(Default)]
pub struct SolverOptions {
    /// `method`: the sweeps' method name.
    pub method: Option<String>,
    /// `gamma`: the relaxation parameter.
    pub gamma: Option<GammaArg>,
    /// `accelerator`: `"newton"`, `"none"` or `"anderson"`.
    pub accelerator: Option<String>,
    /// `coarse`: the rigid-body coarse correction.
    pub coarse: Option<String>,
    /// `tol`: the stopping tolerance.
    pub tol: Option<f64>,
    /// `max_iter`: the iteration cap.
    pub max_iter: Option<usize>,
    /// `u0`: the initial normal displacement.
    pub u0: Option<f64>,
    /// `u_prev`: the two-point methods' initial u⁻¹ₙ.
    pub u_prev: Option<f64>,
    /// `threads`: worker threads.
    pub threads: Option<usize>,
    /// `gap_tol`: the augmented pairs' Signorini tolerance.
    pub gap_tol: Option<f64>,
    /// `equilibrium_tol`: the largest equilibrium residual of a converged result.
    pub equilibrium_tol: Option<f64>,
    /// `balance_tol`: the largest net force and moment of a body of a converged result.
    pub balance_tol: Option<f64>,
    /// `max_updates`: the augmented pairs' cap on multiplier updates.
    pub max_updates: Option<usize>,
    /// `condensation`: `"auto"`, `"dense"` or `"sparse"`.
    pub condensation: Option<String>,
    /// `enforcement`: `"penalty"` or `"augmented"` for every pair (a model option, not a
    /// setting).
    pub enforcement: Option<String>,
    /// `friction`: the tangential law of every pair (a model option, like `enforcement`).
    pub friction: Option<Friction>,
}

fn solver_error(key: &str, message: impl std::fmt::Display) -> PyErr {
    setup_error(SetupError::Solver(format!("{key}: {message}")))
}

impl SolverOptions {
    /// Applies the overrides to `base`, with the checks of a `[solver]` table.
    pub fn apply(&self, base: &Settings) -> PyResult<Settings> {
        let method = match &self.method {
            Some(m) => Some(m.parse::<Method>().map_err(|e| solver_error("method", e))?),
            None => None,
        };
        // The names are those of the `[solver]` table's schema, with its messages.
        let accelerator: Option<AcceleratorSpec> = self
            .accelerator
            .as_deref()
            .map(from_name)
            .transpose()
            .map_err(|e| solver_error("accelerator", e))?;
        let coarse: Option<CoarseSpec> = self
            .coarse
            .as_deref()
            .map(from_name)
            .transpose()
            .map_err(|e| solver_error("coarse", e))?;
        let condensation: Option<Condensation> = self
            .condensation
            .as_deref()
            .map(from_name)
            .transpose()
            .map_err(|e| solver_error("condensation", e))?;
        let spec = SolverSpec {
            method,
            gamma: self.gamma.as_ref().map(gamma_spec).transpose()?,
            accelerator,
            coarse,
            tol: self.tol,
            max_iter: self.max_iter,
            u0: self.u0,
            u_prev: self.u_prev,
            threads: self.threads,
            gap_tol: self.gap_tol,
            equilibrium_tol: self.equilibrium_tol,
            balance_tol: self.balance_tol,
            max_updates: self.max_updates,
            condensation,
            ..SolverSpec::default()
        };
        setup::settings(&spec, base).map_err(setup_error)
    }

    /// The thread count: the option's, else `base`.
    pub fn threads_or(&self, base: Option<usize>) -> Option<usize> {
        self.threads.or(base)
    }

    /// `model` with every pair's enforcement set to the option's (``"penalty"`` or
    /// ``"augmented"``), if given.
    pub fn enforce(&self, mut model: Model) -> PyResult<Model> {
        if let Some(name) = &self.enforcement {
            let e: EnforcementSpec = from_name(name)
                .map_err(|e| setup_error(SetupError::Solver(format!("enforcement: {e}"))))?;
            let e: Enforcement = e.into();
            model.pairs.iter_mut().for_each(|p| p.enforcement = e);
        }
        if let Some(f) = self.friction {
            model.pairs.iter_mut().for_each(|p| p.friction = f);
        }
        Ok(model)
    }
}

/// The `friction=` keyword of `solve`, `solve_steps` and `monolithic`: the text of
/// `--friction` (``"coulomb:0.3"``, ``"tresca:5"``, ``"none"``) or a dict as in
/// `Problem.add_contact` (``{"law": "coulomb", "mu": 0.3}``); `None` keeps each pair's.
pub fn friction_arg(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Friction>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    if let Ok(text) = obj.extract::<String>() {
        return parse_friction(&text)
            .map(Some)
            .map_err(|e| solver_error("friction", e));
    }
    let spec: FrictionSpec =
        parse(obj, "friction")?.map_err(|e| setup_error(SetupError::Solver(e)))?;
    friction_law(&spec)
        .map(Some)
        .map_err(|(key, message)| solver_error(&key, message))
}

/// A γ argument as the `gamma` value of a `[solver]` table: a name is read by the schema's
/// deserializer (only `"auto"`), whose message names the key.
fn gamma_spec(g: &GammaArg) -> PyResult<GammaSpec> {
    match g {
        GammaArg::Value(v) => Ok(GammaSpec::Value(*v)),
        GammaArg::Name(s) => from_name(s).map_err(|e| setup_error(SetupError::Solver(e))),
    }
}

/// A γ argument as a γ rule.
pub fn gamma(g: &GammaArg) -> PyResult<Gamma> {
    setup::gamma(gamma_spec(g)?).map_err(setup_error)
}

/// A γ rule as a Python value: a float, or `"auto"`.
pub fn gamma_to_py(py: Python<'_>, g: Gamma) -> PyResult<Py<PyAny>> {
    Ok(match g {
        Gamma::Constant(v) => v.into_pyobject(py)?.into_any().unbind(),
        Gamma::Auto => "auto".into_pyobject(py)?.into_any().unbind(),
    })
}
