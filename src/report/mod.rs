//! The paper's results of Sec. 5 (Figs. 4-14), and six beyond it (Figs. 15-20), as plans,
//! figures, a summary and a self-contained report page: what `freefloat reproduce` writes.
//!
//! Every number here is computed by the planners on the paper's problem
//! ([`crate::PlanningProblem::paper`]): nothing is copied from the paper except its reported wall
//! times ([`PaperSeconds`]), shown beside ours.
//!
//! ```
//! use freefloat::report::cases;
//!
//! let case = cases().into_iter().find(|c| c.id == "fig06").expect("Fig. 6 is a case");
//! let outcome = case.run().expect("the paper's case has a plan");
//! assert!(outcome.plan.verification.final_error <= 1e-9);
//! assert!(outcome.torques.certificate.certified);
//! ```

pub mod arm;
pub mod arm3;
pub mod arm_figure;
pub mod cases;
pub mod closed_loop;
pub mod figures;
pub mod html;
pub mod io;
pub mod methods;
pub mod out_dir;
pub mod plan_report;
pub use crate::numerics::format as numbers;
pub mod plot;
pub mod reproduce;
pub mod ros;
pub mod summary;

pub use arm_figure::{arm_animation, arm_limit_bounds, arm_plan_figure};
pub use arm3::{
    ARM3_FIGURE, ARM3_LIMITED_FIGURE, Arm3Row, arm3_animation, arm3_figure, arm3_limited_figure, plan_arm3,
    plan_arm3_limited,
};
pub use cases::{Case, CaseMethod, CaseOutcome, PaperSeconds, cases};
pub use figures::{Animation, AnimationLeast, AnimationScene, BASE_SIZE, animation, plan_figure};
pub use methods::{COMPARED_METHODS, METHOD_MOUNTS, MethodRow, methods_markdown};
pub use summary::{
    DOMAIN_FIGURES, DOMAIN_GRID, DomainPanel, DomainRow, StageSeconds, SummaryRow, SweepSummary, domain_panel,
    summary_markdown, sweep_options,
};
