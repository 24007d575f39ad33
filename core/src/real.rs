//! Floating-point abstraction: the CPU reference runs the same code in `f64` (the physics truth)
//! and in `f32` (what the GPU computes). Constants are written in `f64` and converted with
//! [`Real::c`], the way DualSPHysics computes kernel constants in double and stores them as float.

use std::fmt::{self, Debug, Display};
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use std::str::FromStr;

/// The working precision of a backend, as a value: the CPU reference's `T` ([`Real::NAME`]) and
/// a GPU variant's storage and arithmetic.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Precision {
    /// f32.
    F32,
    /// f64 (on the GPU: SHADER_F64).
    F64,
}

impl Precision {
    /// Every value.
    pub const ALL: &'static [Precision] = &[Precision::F32, Precision::F64];
    /// The id component: `f32` or `f64`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
    /// Parses an id component.
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|p| p.name() == s)
    }
    /// Bytes of one real.
    pub fn bytes(self) -> usize {
        match self {
            Precision::F32 => 4,
            Precision::F64 => 8,
        }
    }
}

impl Display for Precision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Precision {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::parse(s).ok_or_else(|| format!("unknown precision `{s}` (f64, f32)"))
    }
}

/// A floating-point type the solver can run in (`f32` or `f64`).
pub trait Real:
    num_traits::Float
    + num_traits::FloatConst
    + Copy
    + Send
    + Sync
    + Default
    + Debug
    + Display
    + bytemuck::Pod
    + std::iter::Sum
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + 'static
{
    /// "f32" or "f64": the name used in variant ids, CSV columns and summaries.
    const NAME: &'static str;
    /// Converts an `f64` constant to this precision (rounding to nearest).
    fn c(x: f64) -> Self;
    /// Widens to `f64` for diagnostics and output.
    fn f64(self) -> f64;
}

impl Real for f32 {
    const NAME: &'static str = "f32";
    #[inline(always)]
    fn c(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn f64(self) -> f64 {
        self as f64
    }
}

impl Real for f64 {
    const NAME: &'static str = "f64";
    #[inline(always)]
    fn c(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn f64(self) -> f64 {
        self
    }
}

/// A 2D vector in the working precision (`vec2<f32>` in WGSL).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct V2<T> {
    /// x component.
    pub x: T,
    /// y component.
    pub y: T,
}

// SAFETY: V2<T> is repr(C) with two fields of the same Pod type and no padding.
unsafe impl<T: bytemuck::Pod> bytemuck::Pod for V2<T> {}
// SAFETY: all-zero bits are a valid V2 of floats.
unsafe impl<T: bytemuck::Zeroable> bytemuck::Zeroable for V2<T> {}

impl<T: Real> V2<T> {
    /// Builds a vector from its components.
    #[inline(always)]
    pub fn new(x: T, y: T) -> Self {
        Self { x, y }
    }
    /// The zero vector.
    #[inline(always)]
    pub fn zero() -> Self {
        Self::new(T::zero(), T::zero())
    }
    /// Builds a vector from `f64` components.
    #[inline(always)]
    pub fn from_f64(x: f64, y: f64) -> Self {
        Self::new(T::c(x), T::c(y))
    }
    /// Dot product.
    #[inline(always)]
    pub fn dot(self, o: Self) -> T {
        self.x * o.x + self.y * o.y
    }
    /// Squared length.
    #[inline(always)]
    pub fn norm2(self) -> T {
        self.x * self.x + self.y * self.y
    }
    /// Length.
    #[inline(always)]
    pub fn norm(self) -> T {
        self.norm2().sqrt()
    }
    /// Converts to the other precision through `f64`.
    #[inline(always)]
    pub fn cast<U: Real>(self) -> V2<U> {
        V2::new(U::c(self.x.f64()), U::c(self.y.f64()))
    }
    /// True when both components are finite.
    #[inline(always)]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
}

impl<T: Real> Add for V2<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y)
    }
}
impl<T: Real> Sub for V2<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y)
    }
}
impl<T: Real> Mul<T> for V2<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        Self::new(self.x * s, self.y * s)
    }
}
impl<T: Real> Div<T> for V2<T> {
    type Output = Self;
    #[inline(always)]
    fn div(self, s: T) -> Self {
        Self::new(self.x / s, self.y / s)
    }
}
impl<T: Real> Neg for V2<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y)
    }
}
impl<T: Real> AddAssign for V2<T> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        self.x += o.x;
        self.y += o.y;
    }
}
impl<T: Real> SubAssign for V2<T> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        self.x -= o.x;
        self.y -= o.y;
    }
}

/// A symmetric traceless 2×2 tensor (the surface stress Π): `[[xx, xy], [xy, -xx]]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Sym2<T> {
    /// Π_xx (= −Π_yy).
    pub xx: T,
    /// Π_xy (= Π_yx).
    pub xy: T,
}

// SAFETY: repr(C), two Pod fields of one type, no padding.
unsafe impl<T: bytemuck::Pod> bytemuck::Pod for Sym2<T> {}
// SAFETY: all-zero bits are valid.
unsafe impl<T: bytemuck::Zeroable> bytemuck::Zeroable for Sym2<T> {}

impl<T: Real> Sym2<T> {
    /// The zero tensor.
    #[inline(always)]
    pub fn zero() -> Self {
        Self { xx: T::zero(), xy: T::zero() }
    }
    /// Tensor times vector.
    #[inline(always)]
    pub fn mul_vec(self, v: V2<T>) -> V2<T> {
        V2::new(self.xx * v.x + self.xy * v.y, self.xy * v.x - self.xx * v.y)
    }
}

impl<T: Real> Add for Sym2<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self { xx: self.xx + o.xx, xy: self.xy + o.xy }
    }
}
impl<T: Real> Sub for Sym2<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self { xx: self.xx - o.xx, xy: self.xy - o.xy }
    }
}
impl<T: Real> Mul<T> for Sym2<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        Self { xx: self.xx * s, xy: self.xy * s }
    }
}
