//! The stage table: the one place that names the stages of a time step and says, for each, when
//! it runs, what it reads and writes, and which control words it clears first. The name is the
//! WGSL entry point of its thread kernel, the CPU function, the pipeline label, the timestamp
//! pass, the profile and bench label and the CSV column; no other Rust file spells it. The CPU
//! loops (`cpu::CpuSolver::evaluate`, `evaluate_stagewise`), the GPU pipelines and readback
//! poisoning (`gpu::stages`, `gpu::readback`), `verify`'s per-stage outputs and the tests all
//! follow from it.

use crate::fields::Field;
use crate::model::ActiveStages;
use crate::scene::Integrator;

/// One stage of a time step: the force-evaluation stages in the order of docs/PHYSICS.md §12, then
/// the integrator's, the blow-up check and the dt reduction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Stage {
    /// Neighbour lists (CPU) or cell ranges / lists (GPU).
    NeighbourSearch,
    /// Contact points (Mode B; reads positions and phases only, so it runs before σ and the
    /// wall typing can end the number-density pass).
    ContactLine,
    /// σ and Holmes χ.
    NumberDensity,
    /// Wall colours by the interpolation line (Mode B, Algorithm 2).
    WallTyping,
    /// ρ = mσ and the pressure.
    EquationOfState,
    /// Colour gradients.
    ColourGradient,
    /// Algorithm 1 (Mode B).
    NormalCorrection,
    /// Surface stress tensor Π.
    SurfaceStress,
    /// Adami wall pressure (R-wall; reads ρ and p, which the surface stages do not touch, so it
    /// can end the colour-gradient pass).
    WallPressure,
    /// Accelerations of the fluid particles.
    Acceleration,
    /// XSPH advection velocity.
    Xsph,
    /// Midpoint predictor half step.
    MidpointPredict,
    /// Midpoint corrector.
    MidpointCorrect,
    /// Velocity Verlet opening kick and drift.
    VerletDrift,
    /// Velocity Verlet closing kick.
    VerletKick,
    /// Blow-up check (non-finite or escaped particles).
    Check,
    /// The cell of every particle and the per-cell counts, the first step of the GPU cell
    /// search, run at the end of the integrator stages that move the particles (the next
    /// search then starts from these counts); no CPU function (the CPU search counts itself).
    CellCount,
    /// The cell starts: the exclusive prefix sum of those counts (the previous starts kept
    /// after them for the next search's merge), run by the last workgroup of the integrator
    /// stages that counted (grids of at most `gpu::plan::FUSED_SCAN_CELLS` cells; the next
    /// search then neither scans nor scatters); no CPU function.
    CellScan,
    /// max |v|, max |a| for the automatic dt.
    ReduceMax,
}

/// How a stage writes a field: every element (the readback poisons it before a lone run), or
/// only some (fluid rows, wall rows, or a correction in place).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Write {
    /// Every particle's element (or the whole contact list).
    All(Field),
    /// The fluid rows.
    Fluid(Field),
    /// Some rows only (walls, or an in-place correction).
    Part(Field),
}

impl Write {
    /// The field written.
    pub fn field(self) -> Field {
        match self {
            All(f) | Fluid(f) | Part(f) => f,
        }
    }
    /// True when no element the comparison reads survives from the input (poison before a run).
    pub fn is_pure(self) -> bool {
        !matches!(self, Part(_))
    }
}

/// Control words a stage resets before it runs (GPU: `ctl` words of `common/bindings.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clear {
    /// The cell counts of the counting sort.
    CellCounts,
    /// The count of contact points found.
    ContactsFound,
    /// The max |v| and max |a| words.
    Maxima,
}

/// Everything the table says about one stage.
#[derive(Clone, Copy, Debug)]
pub struct StageDef {
    /// The stage.
    pub stage: Stage,
    /// Its name (entry point, CPU function, label, CSV column).
    pub name: &'static str,
    /// Fields it reads (besides positions, velocities and the neighbour structure).
    pub reads: &'static [Field],
    /// Fields it writes.
    pub writes: &'static [Write],
    /// Control words reset before it runs.
    pub clears: &'static [Clear],
    /// The passes (by their first stage) this per-particle stage may run at the end of, in the
    /// thread that has just written the particle's output, when it follows that pass (every
    /// stage in between fused too): of what the pass writes it reads only that particle's own
    /// output (anything else it reads comes from earlier passes), and nothing in the pass reads
    /// what it writes, so the fused pass computes what the two passes compute
    /// ([`ActiveStages::evaluation_passes`], [`Stage::opening_passes`], [`Stage::closing_passes`]).
    pub epilogue_of: &'static [Stage],
}

use Field as F;
use Write::{All, Fluid, Part};

const fn def(
    stage: Stage,
    name: &'static str,
    reads: &'static [Field],
    writes: &'static [Write],
    clears: &'static [Clear],
) -> StageDef {
    StageDef { stage, name, reads, writes, clears, epilogue_of: &[] }
}

/// `d` as an epilogue of the passes that start with one of `heads`.
const fn epilogue(d: StageDef, heads: &'static [Stage]) -> StageDef {
    StageDef { epilogue_of: heads, ..d }
}

/// The table, in [`Stage`] order.
pub static TABLE: [StageDef; 19] = [
    def(Stage::NeighbourSearch, "neighbour_search", &[], &[], &[Clear::CellCounts]),
    def(Stage::ContactLine, "contact_line", &[], &[All(F::Contacts)], &[Clear::ContactsFound]),
    def(Stage::NumberDensity, "number_density", &[], &[All(F::Sigma), All(F::Chi)], &[]),
    // A wall's colour and mass from the contact points of the pass before and its own position
    // (σ reads neither), so it ends the number-density pass, before the EOS that reads them.
    epilogue(
        def(Stage::WallTyping, "wall_typing", &[F::Contacts], &[Part(F::Colour), Part(F::Mass)], &[]),
        &[Stage::NumberDensity],
    ),
    epilogue(
        def(
            Stage::EquationOfState,
            "equation_of_state",
            &[F::Sigma, F::Mass, F::Colour],
            &[All(F::Rho), All(F::P)],
            &[],
        ),
        &[Stage::NumberDensity],
    ),
    def(Stage::ColourGradient, "colour_gradient", &[F::Sigma, F::Colour], &[All(F::Grad)], &[]),
    epilogue(
        def(Stage::NormalCorrection, "normal_correction", &[F::Grad, F::Colour, F::Contacts], &[Part(F::Grad)], &[]),
        &[Stage::ColourGradient],
    ),
    epilogue(
        def(Stage::SurfaceStress, "surface_stress", &[F::Grad, F::Colour], &[All(F::Pi)], &[]),
        &[Stage::ColourGradient],
    ),
    // A wall's pressure from its fluid neighbours' ρ and p (the number-density pass's), in the
    // thread of the colour-gradient pass that has just written the wall's gradient: that pass
    // reads no p.
    epilogue(def(Stage::WallPressure, "wall_pressure", &[F::Rho, F::P], &[Part(F::P)], &[]), &[Stage::ColourGradient]),
    def(Stage::Acceleration, "acceleration", &[F::Sigma, F::Chi, F::Mass, F::P, F::Pi], &[Fluid(F::Acc)], &[]),
    def(Stage::Xsph, "xsph", &[F::Mass, F::Rho], &[Fluid(F::Vt)], &[]),
    def(Stage::MidpointPredict, "midpoint_predict", &[F::Acc, F::Vt], &[], &[]),
    def(Stage::MidpointCorrect, "midpoint_correct", &[F::Acc, F::Vt], &[], &[]),
    def(Stage::VerletDrift, "verlet_drift", &[F::Acc, F::Vt], &[], &[]),
    def(Stage::VerletKick, "verlet_kick", &[F::Acc], &[Part(F::Vt)], &[]),
    // The blow-up check of each particle right after its closing integration (the step number
    // it records is the one being completed; the clock ticks once every particle is done).
    epilogue(def(Stage::Check, "check", &[F::Acc], &[], &[]), &[Stage::MidpointCorrect, Stage::VerletKick]),
    // Each particle's cell, counted right after it moved (walls counted where they stand).
    epilogue(
        def(Stage::CellCount, "cell_count", &[], &[], &[Clear::CellCounts]),
        &[Stage::MidpointPredict, Stage::MidpointCorrect, Stage::VerletDrift, Stage::VerletKick],
    ),
    // The cell starts from those counts, once every workgroup of the pass has counted.
    epilogue(
        def(Stage::CellScan, "cell_scan", &[], &[], &[]),
        &[Stage::MidpointPredict, Stage::MidpointCorrect, Stage::VerletDrift, Stage::VerletKick],
    ),
    def(Stage::ReduceMax, "reduce_max", &[F::Acc], &[], &[Clear::Maxima]),
];

impl Stage {
    /// Every stage, in table order.
    pub const ALL: [Stage; 19] = {
        let mut all = [Stage::NeighbourSearch; 19];
        let mut k = 0;
        while k < 19 {
            all[k] = TABLE[k].stage;
            k += 1;
        }
        all
    };

    /// The stages of one force evaluation, in order (whether active or not).
    pub const EVALUATION: [Stage; 11] = [
        Stage::NeighbourSearch,
        Stage::ContactLine,
        Stage::NumberDensity,
        Stage::WallTyping,
        Stage::EquationOfState,
        Stage::ColourGradient,
        Stage::NormalCorrection,
        Stage::SurfaceStress,
        Stage::WallPressure,
        Stage::Acceleration,
        Stage::Xsph,
    ];

    /// The table row.
    pub const fn def(self) -> &'static StageDef {
        &TABLE[self as usize]
    }

    /// The name.
    pub const fn name(self) -> &'static str {
        self.def().name
    }

    /// The stage of a name.
    pub fn from_name(name: &str) -> Option<Stage> {
        TABLE.iter().find(|d| d.name == name).map(|d| d.stage)
    }

    /// True when a force evaluation of a scene with `st` runs this stage (evaluation stages
    /// only; the step stages follow from [`Stage::step_pair`]).
    pub fn is_active(self, st: &ActiveStages) -> bool {
        match self {
            Stage::ContactLine => st.contact_line,
            Stage::WallTyping => st.wall_typing,
            Stage::WallPressure => st.wall_pressure,
            Stage::ColourGradient | Stage::SurfaceStress => st.surface_tension,
            Stage::NormalCorrection => st.surface_tension && st.normal_correction,
            Stage::Xsph => st.xsph,
            Stage::NeighbourSearch | Stage::NumberDensity | Stage::EquationOfState | Stage::Acceleration => true,
            _ => false,
        }
    }

    /// The (before, after) stages around the second evaluation of a step of `integrator`.
    pub fn step_pair(integrator: Integrator) -> (Stage, Stage) {
        match integrator {
            Integrator::Midpoint => (Stage::MidpointPredict, Stage::MidpointCorrect),
            Integrator::Verlet | Integrator::VerletPec => (Stage::VerletDrift, Stage::VerletKick),
        }
    }

    /// The opening integrator stage of a step of `integrator` as passes, followed by the
    /// cell stages of the moved particles `cells` gives ([`CellEpilogues::stages`]).
    pub fn opening_passes(integrator: Integrator, cells: CellEpilogues) -> Vec<Vec<Stage>> {
        let mut open = vec![Stage::step_pair(integrator).0];
        open.extend(cells.stages());
        passes(&open)
    }

    /// The end of a step of `integrator` as passes: its closing stage, then `check`, then the
    /// cell stages `cells` gives; one pass: all are epilogues of the closing stage.
    pub fn closing_passes(integrator: Integrator, cells: CellEpilogues) -> Vec<Vec<Stage>> {
        let mut close = vec![Stage::step_pair(integrator).1, Stage::Check];
        close.extend(cells.stages());
        passes(&close)
    }

    /// Fields written to every element (poisoned before a lone GPU run).
    pub fn pure_outputs(self) -> impl Iterator<Item = Field> {
        self.def().writes.iter().filter(|w| w.is_pure()).map(|w| w.field())
    }

    /// Every field written.
    pub fn outputs(self) -> impl Iterator<Item = Field> {
        self.def().writes.iter().map(|w| w.field())
    }
}

/// The cell stages that follow the integrator stages: none (the `direct` search), the count
/// ([`Stage::CellCount`]: the search scans and scatters), or the count and the scan
/// ([`Stage::CellScan`]: the search only merges the previous lists into the new ones).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellEpilogues {
    /// No cells.
    None,
    /// The cell counts.
    Count,
    /// The counts and the cell starts.
    CountAndScan,
}

impl CellEpilogues {
    /// The stages, in order.
    pub fn stages(self) -> &'static [Stage] {
        match self {
            CellEpilogues::None => &[],
            CellEpilogues::Count => &[Stage::CellCount],
            CellEpilogues::CountAndScan => &[Stage::CellCount, Stage::CellScan],
        }
    }
}

impl std::fmt::Display for Stage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl ActiveStages {
    /// The stages of one force evaluation of this scene, in order.
    pub fn evaluation(&self) -> Vec<Stage> {
        Stage::EVALUATION.into_iter().filter(|s| s.is_active(self)).collect()
    }

    /// Their names (printed and written into the run summary).
    pub fn names(&self) -> Vec<&'static str> {
        self.evaluation().into_iter().map(Stage::name).collect()
    }

    /// The evaluation as passes: each stage starts a pass unless it is an epilogue of the pass
    /// being built (its [`StageDef::epilogue_of`] names that pass's first stage), then it joins it.
    pub fn evaluation_passes(&self) -> Vec<Vec<Stage>> {
        passes(&self.evaluation())
    }
}

/// `stages` (in order) grouped into passes by the table's [`StageDef::epilogue_of`].
pub fn passes(stages: &[Stage]) -> Vec<Vec<Stage>> {
    let mut out: Vec<Vec<Stage>> = Vec::new();
    for &s in stages {
        match out.last_mut() {
            Some(pass) if s.def().epilogue_of.contains(&pass[0]) => pass.push(s),
            _ => out.push(vec![s]),
        }
    }
    out
}

/// The label of a pass: its stages' names joined by `+`.
pub fn pass_label(pass: &[Stage]) -> String {
    pass.iter().map(|s| s.name()).collect::<Vec<_>>().join("+")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_rows_follow_the_enum_and_names_are_unique() {
        for (k, d) in TABLE.iter().enumerate() {
            assert_eq!(d.stage as usize, k, "{}", d.name);
            assert_eq!(Stage::from_name(d.name), Some(d.stage));
        }
        assert!(Stage::EVALUATION.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn epilogues_join_the_pass_they_follow() {
        use Stage::*;
        let drop = [NeighbourSearch, NumberDensity, EquationOfState, ColourGradient, SurfaceStress, Acceleration];
        let p = passes(&drop);
        assert_eq!(
            p,
            vec![
                vec![NeighbourSearch],
                vec![NumberDensity, EquationOfState],
                vec![ColourGradient, SurfaceStress],
                vec![Acceleration]
            ]
        );
        assert_eq!(pass_label(&p[1]), "number_density+equation_of_state");
        // Mode B: the contact points first, then σ with the wall typing and the EOS of the
        // typed walls in one pass.
        let mode_b =
            [ContactLine, NumberDensity, WallTyping, EquationOfState, ColourGradient, NormalCorrection, SurfaceStress];
        assert_eq!(passes(&mode_b).len(), 3);
        assert_eq!(passes(&mode_b)[1], vec![NumberDensity, WallTyping, EquationOfState]);
        assert_eq!(passes(&mode_b)[2], vec![ColourGradient, NormalCorrection, SurfaceStress]);
        // The wall pressure ends the colour-gradient pass, or is a pass of its own without one.
        assert_eq!(
            passes(&[EquationOfState, ColourGradient, SurfaceStress, WallPressure, Acceleration])[1],
            vec![ColourGradient, SurfaceStress, WallPressure]
        );
        assert_eq!(passes(&[NumberDensity, EquationOfState, WallPressure, Acceleration]).len(), 3);
        // Wall typing never joins a pass that does not compute σ.
        assert_eq!(passes(&[ContactLine, WallTyping]).len(), 2);
        // The check ends the closing integrator stage, never the opening one; the cell count
        // ends both when the search has cells.
        use CellEpilogues as C;
        assert_eq!(Stage::closing_passes(Integrator::Midpoint, C::None), vec![vec![MidpointCorrect, Check]]);
        assert_eq!(Stage::closing_passes(Integrator::Verlet, C::Count), vec![vec![VerletKick, Check, CellCount]]);
        assert_eq!(
            Stage::closing_passes(Integrator::Midpoint, C::CountAndScan),
            vec![vec![MidpointCorrect, Check, CellCount, CellScan]]
        );
        assert_eq!(Stage::opening_passes(Integrator::Midpoint, C::Count), vec![vec![MidpointPredict, CellCount]]);
        assert_eq!(
            Stage::opening_passes(Integrator::Midpoint, C::CountAndScan),
            vec![vec![MidpointPredict, CellCount, CellScan]]
        );
        assert_eq!(Stage::opening_passes(Integrator::Verlet, C::None), vec![vec![VerletDrift]]);
        assert_eq!(passes(&[MidpointPredict, Check]).len(), 2);
        assert_eq!(passes(&[Acceleration, CellCount]).len(), 2);
        assert_eq!(passes(&[Acceleration, CellScan]).len(), 2);
    }
}
