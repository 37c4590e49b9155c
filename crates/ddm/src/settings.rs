//! The settings of one DD solve: which interface iteration runs ([`Accelerator`]), its Robin
//! rule and relaxation for the sweeps, the tolerances and caps, and their validation.

use crate::coarse::CoarseMode;
use crate::condensed::Condensation;
use crate::error::SetupError;
use crate::method::Method;
use crate::relaxation::Gamma;

/// Which interface iteration runs: the Robin sweeps, relaxed or accelerated, or the interface
/// Newton method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Accelerator {
    /// Relaxation with γ only (the paper's iteration).
    None,
    /// Anderson acceleration (IQN-ILS) with at most `depth` secant pairs.
    Anderson {
        /// Memory: the number of secant pairs kept.
        depth: usize,
    },
    /// The interface semismooth Newton method of [`crate::newton`] (the method and γ are unused).
    Newton,
}

impl std::fmt::Display for Accelerator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Accelerator::None => f.write_str("none"),
            Accelerator::Anderson { depth } => write!(f, "anderson({depth})"),
            Accelerator::Newton => f.write_str("newton"),
        }
    }
}

/// Default Anderson memory: enough to act as GMRES over the few tens of iterations the two-level
/// iteration takes, small against any interface.
pub const ANDERSON_DEPTH: usize = 40;

/// Default largest equilibrium residual of a converged result: 1 % of the total contact force.
/// The relative-change test bounds the last step, not the remaining error; converged solves of
/// slowly contracting problems carry residuals up to about 1e−3 at tol = 1e−6, while an iteration
/// stopped far from its fixed point (a tiny γ) is off by tens of percent.
pub const EQUILIBRIUM_TOL: f64 = 1e-2;

/// Default largest net force and moment of a body of a converged result under the interface
/// Newton method, relative to the largest force total of a body ([`crate::force_balance`]). The
/// Robin sweeps, which stop on a change rather than a residual, default to the equilibrium
/// tolerance instead ([`Settings::balance_limit`]).
pub const BALANCE_TOL: f64 = 1e-6;

/// Settings of one DD solve.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Robin coefficient rule.
    pub method: Method,
    /// Relaxation parameter γ (with Anderson: the relaxation of the first step).
    pub gamma: Gamma,
    /// How the sweeps' outputs are combined.
    pub accelerator: Accelerator,
    /// Which bodies the rigid-body coarse correction moves into balance before every sweep.
    pub coarse: CoarseMode,
    /// Stopping tolerance on every body's relative change (relaxation) or residual (Anderson).
    pub tol: f64,
    /// Largest equilibrium residual (relative to the total contact force) a converged result may
    /// have; above it the solve reports [`crate::outcome::Stop::Stalled`].
    pub equilibrium_tol: f64,
    /// Largest net force and moment of a body a converged result may have, relative to the
    /// largest force total of a body; `None`: [`Settings::balance_limit`]'s default. Above it
    /// the solve reports [`crate::outcome::Stop::Unbalanced`].
    pub balance_tol: Option<f64>,
    /// Iteration cap.
    pub max_iter: usize,
    /// Initial normal displacement u^0_n on all contact points.
    pub u0: f64,
    /// Initial u^{−1}_n (two-point methods).
    pub u_prev: f64,
    /// Augmented Lagrangian pairs: the largest violation of the Signorini conditions (a length)
    /// of a converged result; `None`: `tol` times the largest normal displacement of the contact
    /// points ([`crate::augmented`]).
    pub gap_tol: Option<f64>,
    /// Augmented Lagrangian pairs: the cap on multiplier updates (inner solves).
    pub max_updates: usize,
    /// How the bodies are condensed on their contact points; read by the callers of
    /// [`crate::solver::prepare_with`] (the iteration itself works on either path).
    pub condensation: Condensation,
}

impl Settings {
    /// The paper's iteration: `method` with a relaxation rule `gamma`, no accelerator, no coarse
    /// correction, the other values as in [`Settings::default`].
    pub fn paper(method: Method, gamma: Gamma) -> Settings {
        Settings {
            method,
            gamma,
            accelerator: Accelerator::None,
            coarse: CoarseMode::Off,
            ..Settings::default()
        }
    }
}

impl Settings {
    /// Anderson acceleration of `active-set` sweeps (γ = 1 for the first step) without coarse
    /// correction; the other values as in [`Settings::default`].
    pub fn anderson() -> Settings {
        Settings {
            method: Method::ActiveSet,
            gamma: Gamma::Constant(1.0),
            accelerator: Accelerator::Anderson {
                depth: ANDERSON_DEPTH,
            },
            coarse: CoarseMode::Off,
            ..Settings::default()
        }
    }
}

impl Settings {
    /// The two-level sweeps: `newton-kurchatov` Robin sweeps with Aitken's `auto` relaxation and
    /// the rigid-body coarse correction of chains of floating bodies; the other values as in
    /// [`Settings::default`].
    pub fn two_level() -> Settings {
        Settings {
            method: Method::NewtonKurchatov,
            gamma: Gamma::Auto,
            accelerator: Accelerator::None,
            coarse: CoarseMode::Chains,
            ..Settings::default()
        }
    }

    /// Called when a Robin rule (a method or γ) is asked for without an accelerator: the
    /// interface Newton method uses neither, so it gives way to the two-level sweeps.
    pub fn use_sweeps(&mut self) {
        if self.accelerator == Accelerator::Newton {
            self.accelerator = Accelerator::None;
            self.coarse = CoarseMode::Chains;
        }
    }

    /// The iteration that runs, as one word: `interface-newton` or `robin-sweeps`.
    pub fn iteration(&self) -> &'static str {
        match self.accelerator {
            Accelerator::Newton => "interface-newton",
            Accelerator::None | Accelerator::Anderson { .. } => "robin-sweeps",
        }
    }

    /// What the iteration's stopping test compares with `tol` (a record's
    /// [`crate::outcome::Record::measure`]).
    pub fn measure_name(&self) -> &'static str {
        match self.accelerator {
            Accelerator::Newton => "relative residual",
            Accelerator::None => "relative change",
            Accelerator::Anderson { .. } => "relative residual of the sweep",
        }
    }

    /// The iteration in words: `interface newton`, or the method and γ rule, with the accelerator
    /// and coarse mode when used.
    pub fn scheme(&self) -> String {
        if self.accelerator == Accelerator::Newton {
            return "interface newton".into();
        }
        let mut text = format!("{}, gamma {}", self.method, self.gamma);
        if self.accelerator != Accelerator::None {
            text += &format!(", accelerator {}", self.accelerator);
        }
        if self.coarse != CoarseMode::Off {
            text += &format!(", coarse {}", self.coarse);
        }
        text
    }
}

/// What a setting must be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Requirement {
    /// A positive finite number.
    Positive,
    /// A positive finite number (γ, which may also be `auto`).
    PositiveOrAuto,
    /// A positive finite length.
    PositiveLength,
    /// A count of at least 1.
    AtLeastOne,
    /// A finite number.
    Finite,
}

/// A setting outside its range: its key in problem files, what it must be, and the value given.
#[derive(Clone, Debug, PartialEq)]
pub struct InvalidSetting {
    /// The key, as problem files, the command line and Python name it.
    pub key: &'static str,
    /// What it must be.
    pub requirement: Requirement,
    /// The value given.
    pub value: f64,
}

impl InvalidSetting {
    /// "must be …, got v", with the value written by `number`.
    pub fn reason(&self, number: impl Fn(f64) -> String) -> String {
        let what = match self.requirement {
            Requirement::Positive => "a positive number",
            Requirement::PositiveOrAuto => "a positive number or \"auto\"",
            Requirement::PositiveLength => "a positive length",
            Requirement::AtLeastOne => "at least 1",
            Requirement::Finite => "finite",
        };
        format!("must be {what}, got {}", number(self.value))
    }
}

impl std::fmt::Display for InvalidSetting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.key, self.reason(|v| v.to_string()))
    }
}

impl From<InvalidSetting> for SetupError {
    fn from(e: InvalidSetting) -> Self {
        SetupError::Solver(e.to_string())
    }
}

impl Settings {
    /// Checks every value a caller can set out of range, in the order of the problem file's
    /// `[solver]` keys; the first one out of range is the error. The problem-file reader, the
    /// command line, Python and [`crate::solver::solve`] all check settings here.
    pub fn validate(&self) -> Result<(), InvalidSetting> {
        fn positive(v: f64) -> bool {
            v.is_finite() && v > 0.0
        }
        fn at_least_one(v: f64) -> bool {
            v >= 1.0
        }
        let count = |n: usize| n as f64;
        let checks: [(&'static str, Requirement, Option<f64>, fn(f64) -> bool); 9] = [
            (
                "gamma",
                Requirement::PositiveOrAuto,
                self.constant_gamma(),
                positive,
            ),
            ("tol", Requirement::Positive, Some(self.tol), positive),
            (
                "equilibrium-tol",
                Requirement::Positive,
                Some(self.equilibrium_tol),
                positive,
            ),
            (
                "balance-tol",
                Requirement::Positive,
                self.balance_tol,
                positive,
            ),
            (
                "max-iter",
                Requirement::AtLeastOne,
                Some(count(self.max_iter)),
                at_least_one,
            ),
            (
                "gap-tol",
                Requirement::PositiveLength,
                self.gap_tol,
                positive,
            ),
            (
                "max-updates",
                Requirement::AtLeastOne,
                Some(count(self.max_updates)),
                at_least_one,
            ),
            ("u0", Requirement::Finite, Some(self.u0), f64::is_finite),
            (
                "u-prev",
                Requirement::Finite,
                Some(self.u_prev),
                f64::is_finite,
            ),
        ];
        for (key, requirement, value, valid) in checks {
            if let Some(value) = value.filter(|&v| !valid(v)) {
                return Err(InvalidSetting {
                    key,
                    requirement,
                    value,
                });
            }
        }
        Ok(())
    }

    /// The largest relative net force and moment of a body that a converged result may have:
    /// `balance_tol`, or by default [`BALANCE_TOL`] under the interface Newton method and the
    /// equilibrium tolerance under the Robin sweeps, whose change test bounds the last step
    /// rather than the remaining residual.
    pub fn balance_limit(&self) -> f64 {
        self.balance_tol.unwrap_or(match self.accelerator {
            Accelerator::Newton => BALANCE_TOL,
            Accelerator::None | Accelerator::Anderson { .. } => self.equilibrium_tol,
        })
    }

    fn constant_gamma(&self) -> Option<f64> {
        match self.gamma {
            Gamma::Constant(g) => Some(g),
            Gamma::Auto => None,
        }
    }
}

/// The one description of the settings that every interface prints: the iteration (with the
/// method, γ, accelerator and coarse mode of the sweeps), the tolerance and the iteration cap.
impl std::fmt::Display for Settings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}, tol {:e}, max-iter {}",
            self.scheme(),
            self.tol,
            self.max_iter
        )
    }
}

impl Default for Settings {
    /// The interface Newton method ([`crate::newton`]); tolerance 1e−6; the paper's initial
    /// values u^0 = 1e−4, u^{−1} = 2e−4. The method and γ (`newton-kurchatov`, `auto`) are those of
    /// the sweeps a caller switches to with [`Settings::use_sweeps`].
    fn default() -> Settings {
        Settings {
            method: Method::NewtonKurchatov,
            gamma: Gamma::Auto,
            accelerator: Accelerator::Newton,
            coarse: CoarseMode::Off,
            tol: 1e-6,
            equilibrium_tol: EQUILIBRIUM_TOL,
            balance_tol: None,
            max_iter: 500,
            u0: 1e-4,
            u_prev: 2e-4,
            gap_tol: None,
            max_updates: 100,
            condensation: Condensation::Auto,
        }
    }
}
