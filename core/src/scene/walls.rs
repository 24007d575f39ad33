//! The wall side of a scene: the contact-angle model at the bottom wall (docs/PHYSICS.md §8)
//! and the wall treatment (pressure, ghost velocity, §6), as plain TOML data.

use serde::{Deserialize, Serialize};

/// Contact-angle mode at the bottom wall (§8).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Contact {
    /// none | a | b.
    pub mode: ContactMode,
    /// Mode A: σ between the wall and fluid phase 0 (σ_LS).
    #[serde(default)]
    pub sigma_ls: f64,
    /// Mode A: σ between the wall and fluid phase 1 (σ_GS).
    #[serde(default)]
    pub sigma_gs: f64,
    /// Mode B: the desired angle θ_d in degrees (inside the liquid, phase 0).
    #[serde(default = "default_theta")]
    pub theta_deg: f64,
    /// Mode B: Algorithm 1 (normal correction) on/off.
    #[serde(default = "yes")]
    pub normal_correction: bool,
    /// Mode B: Algorithm 2 (wall typing by the interpolation line) on/off.
    #[serde(default = "yes")]
    pub wall_typing: bool,
    /// Mode B: the contact-line band is 0 < y − y_w ≤ band·Δx (thesis 1.2).
    #[serde(default = "default_band")]
    pub band: f64,
    /// Mode A: the contact-line force that carries the half of σ_GS − σ_LS the fluid side of the
    /// wall bands does not (docs/PHYSICS.md §8.2.1). Off by default: it overshoots Young's angle
    /// (the wall bands alone stop short of it).
    #[serde(default)]
    pub line_force: bool,
    /// Mode A: whether fluid–wall pairs carry the liquid–gas part of the fluid's stress tensor
    /// (`shared`, default: the wall pairs then take back part of that interface's pull where it
    /// meets the wall) or not (`free`; docs/PHYSICS.md §8.2.2).
    #[serde(default)]
    pub liquid_gas_at_wall: LiquidGasAtWall,
    /// Mode A: where σ_LS and σ_GS act (docs/PHYSICS.md §8.2.3): in stress bands along the wall
    /// (`bands`, default) or as the line force σ_GS − σ_LS at each contact point alone (`line`).
    #[serde(default)]
    pub wall_tension: WallTension,
    /// Mode A's contact-line force: how it is shared among the fluid particles near each contact
    /// point (docs/PHYSICS.md §8.2.4).
    #[serde(default)]
    pub line_force_spread: LineForceSpread,
}

/// Mode A: how the contact-line force is shared near each contact point (docs/PHYSICS.md §8.2.4).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum LineForceSpread {
    /// By the kernel of the distance to the contact point (§8.2.1).
    #[default]
    Kernel,
    /// By the liquid–gas colour gradient times the wall's kernel sum, within two supports.
    Interface,
}

/// Mode A: where the wall's two tensions act (docs/PHYSICS.md §8.2.3).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum WallTension {
    /// The wall is a third colour: S–L and S–G stress bands (T75), `contact.line_force` optional.
    #[default]
    Bands,
    /// No wall band; the whole σ_GS − σ_LS acts on the fluid at each contact point.
    Line,
    /// No wall band; the wall typed at each contact point's measured angle θ_d (the liquid–gas
    /// band continues into it) and the unbalanced Young force `σ_GS − σ_LS − σ_LG cos θ_d` at the
    /// line (docs/PHYSICS.md §8.2.5).
    Unbalanced,
}

/// Mode A: what the wall does with the liquid–gas interface's stress where it meets the wall
/// (docs/PHYSICS.md §8.2.2).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum LiquidGasAtWall {
    /// Fluid–wall pairs carry the fluid's whole tensor (T76 over every neighbour).
    #[default]
    Shared,
    /// Fluid–wall pairs leave out the liquid–gas part of the fluid's tensor.
    Free,
}

fn default_theta() -> f64 {
    90.0
}
fn yes() -> bool {
    true
}
fn default_band() -> f64 {
    1.2
}

impl Default for Contact {
    fn default() -> Self {
        Self {
            mode: ContactMode::None,
            sigma_ls: 0.0,
            sigma_gs: 0.0,
            theta_deg: 90.0,
            normal_correction: true,
            wall_typing: true,
            band: 1.2,
            line_force: false,
            liquid_gas_at_wall: LiquidGasAtWall::Shared,
            wall_tension: WallTension::Bands,
            line_force_spread: LineForceSpread::Kernel,
        }
    }
}

/// The contact-angle modes.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ContactMode {
    /// Walls carry no colour.
    None,
    /// Mode A: walls are a third phase with σ_LS, σ_GS (Young).
    A,
    /// Mode B: one coefficient plus Algorithms 1 and 2.
    B,
}

/// Wall treatment (§6).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Walls {
    /// t-wall (EOS of the wall's phase) or r-wall (Adami extrapolation).
    #[serde(default = "default_wall_pressure")]
    pub pressure: WallPressure,
    /// morris (geometric distances) or holmes (state ratio χ).
    #[serde(default = "default_wall_velocity")]
    pub velocity: WallVelocity,
    /// Cap β_max of the ghost-velocity factor.
    #[serde(default = "default_beta_max")]
    pub beta_max: f64,
    /// The phase whose mass and EOS untyped wall particles use.
    #[serde(default)]
    pub phase: Option<String>,
    /// Lennard-Jones strength D (0 = off); r0 = Δx/2.
    #[serde(default)]
    pub lj_strength: f64,
}

fn default_wall_pressure() -> WallPressure {
    WallPressure::TWall
}
fn default_wall_velocity() -> WallVelocity {
    WallVelocity::Morris
}
fn default_beta_max() -> f64 {
    1.5
}

impl Default for Walls {
    fn default() -> Self {
        Self {
            pressure: WallPressure::TWall,
            velocity: WallVelocity::Morris,
            beta_max: 1.5,
            phase: None,
            lj_strength: 0.0,
        }
    }
}

/// Wall pressure options (§6.1).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum WallPressure {
    /// Thesis: `ρ_w = m_w σ_w`, EOS of the wall's (typed) phase.
    TWall,
    /// Adami–Hu–Adams 2012 extrapolation from the fluid neighbours.
    RWall,
}

/// Wall ghost-velocity options (§6.2, §6.4).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum WallVelocity {
    /// Geometric distances to the nearest wall line.
    Morris,
    /// Holmes state ratio χ.
    Holmes,
}
