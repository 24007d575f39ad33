// kernel.wgsl: 2D smoothing kernels (docs/PHYSICS.md §1, thesis T40–T43).
// WGSL twin of src/physics/kernel.rs (kernel_f, kernel_df, kernel_w, kernel_dwdr): same names,
// same argument order, same operation order, so f32 results agree to rounding level.
// W(r,h) = α f(q) and ∂W/∂r = (α/h) f'(q) with q = r/h and α = α_2D/h² (constants computed on
// the host in f64, stored in `real`). The kernel is chosen by an integer id in the order of
// `KernelKind::ALL`, read from uniform data, so one pipeline serves every kernel.
// Library module: functions, structs and consts only (no bindings, no entry points).

const KERNEL_CUBIC_SPLINE: u32 = 0u; // Monaghan cubic spline (T42), support 2h
const KERNEL_QUINTIC: u32 = 1u;      // Morris quintic spline (T43), support 3h
const KERNEL_JOHNSON: u32 = 2u;      // Johnson quadratic (T41), support 2h
const KERNEL_GAUSSIAN: u32 = 3u;     // truncated Gaussian (T40), support 3h
const KERNEL_WENDLAND_C2: u32 = 4u;  // Wendland C2 (not in the thesis), support 2h

// Twin of `KernelParams<T>`: `kind` is `KernelKind::id()`.
struct KernelParams {
    kind: u32,
    h: real,
    inv_h: real,
    alpha: real,
    support: real,
}

// a⁵, the quintic's building block.
fn kernel_p5(a: real) -> real {
    let a2 = a * a;
    return a2 * a2 * a;
}

// a⁴, the quintic derivative's building block.
fn kernel_p4(a: real) -> real {
    let a2 = a * a;
    return a2 * a2;
}

// e^x. NOTE: GLSL.std.450 Exp is defined for 16/32-bit floats only, so the f64 build evaluates
// it in f32 (relative error ~1e-7, not 1e-16: the Gaussian is the one f64 kernel at f32 accuracy).
fn kernel_exp(x: real) -> real {
#ifdef F64
    return real(exp(f32(x)));
#else
    return exp(x);
#endif
}

// Dimensionless kernel shape f(q) (zero outside the support).
fn kernel_f(kind: u32, q: real) -> real {
    switch kind {
        case KERNEL_CUBIC_SPLINE: {
            if q < real(1.0) {
                return real(1.0) - real(1.5) * q * q + real(0.75) * q * q * q;
            } else if q < real(2.0) {
                let a = real(2.0) - q;
                return real(0.25) * a * a * a;
            }
            return real(0.0);
        }
        case KERNEL_QUINTIC: {
            if q < real(1.0) {
                return kernel_p5(real(3.0) - q) - real(6.0) * kernel_p5(real(2.0) - q)
                    + real(15.0) * kernel_p5(real(1.0) - q);
            } else if q < real(2.0) {
                return kernel_p5(real(3.0) - q) - real(6.0) * kernel_p5(real(2.0) - q);
            } else if q < real(3.0) {
                return kernel_p5(real(3.0) - q);
            }
            return real(0.0);
        }
        case KERNEL_JOHNSON: {
            if q < real(2.0) {
                let a = real(2.0) - q;
                return real(0.1875) * a * a;
            }
            return real(0.0);
        }
        case KERNEL_GAUSSIAN: {
            if q < real(3.0) {
                return kernel_exp(-q * q);
            }
            return real(0.0);
        }
        default: { // KERNEL_WENDLAND_C2
            if q < real(2.0) {
                let a = real(1.0) - real(0.5) * q;
                let a2 = a * a;
                return a2 * a2 * (real(2.0) * q + real(1.0));
            }
            return real(0.0);
        }
    }
}

// Derivative of the shape, f'(q) (≤ 0; zero outside the support).
fn kernel_df(kind: u32, q: real) -> real {
    switch kind {
        case KERNEL_CUBIC_SPLINE: {
            if q < real(1.0) {
                return real(-3.0) * q + real(2.25) * q * q;
            } else if q < real(2.0) {
                let a = real(2.0) - q;
                return real(-0.75) * a * a;
            }
            return real(0.0);
        }
        case KERNEL_QUINTIC: {
            // NOTE: at q → 0 the three terms cancel (−405 + 480 − 75 = 0): compare with an
            // absolute floor at the scale of the terms, not relative to f'(q).
            if q < real(1.0) {
                return real(-5.0) * kernel_p4(real(3.0) - q) + real(30.0) * kernel_p4(real(2.0) - q)
                    - real(75.0) * kernel_p4(real(1.0) - q);
            } else if q < real(2.0) {
                return real(-5.0) * kernel_p4(real(3.0) - q) + real(30.0) * kernel_p4(real(2.0) - q);
            } else if q < real(3.0) {
                return real(-5.0) * kernel_p4(real(3.0) - q);
            }
            return real(0.0);
        }
        case KERNEL_JOHNSON: {
            if q < real(2.0) {
                return real(-0.375) * (real(2.0) - q);
            }
            return real(0.0);
        }
        case KERNEL_GAUSSIAN: {
            if q < real(3.0) {
                return real(-2.0) * q * kernel_exp(-q * q);
            }
            return real(0.0);
        }
        default: { // KERNEL_WENDLAND_C2
            if q < real(2.0) {
                let a = real(1.0) - real(0.5) * q;
                return real(-5.0) * q * a * a * a;
            }
            return real(0.0);
        }
    }
}

// W(r, h).
fn kernel_w(kp: KernelParams, r: real) -> real {
    return kp.alpha * kernel_f(kp.kind, r * kp.inv_h);
}

// ∂W/∂r (r, h) = F'(r), ≤ 0.
fn kernel_dwdr(kp: KernelParams, r: real) -> real {
    return kp.alpha * kp.inv_h * kernel_df(kp.kind, r * kp.inv_h);
}
