//! The PSD cones' sandwich products svec(B V Bᵀ) of [`super`]'s scalings, unrolled per block size
//! and compiled for AVX2 where the processor has it.

pub(super) const SQ2: f64 = std::f64::consts::SQRT_2;

/// Scratch for one PSD block's sandwich, sized for the largest block.
pub(super) struct Scratch {
    pub(super) v: Vec<f64>,
    pub(super) t: Vec<f64>,
    pub(super) o: Vec<f64>,
}

impl Scratch {
    pub(super) fn new(n: usize) -> Scratch {
        Scratch { v: vec![0.0; n * n], t: vec![0.0; n * n], o: vec![0.0; n * n] }
    }
}

/// [`sandwich`] for the block sizes of seed 003's programs, on arrays the compiler unrolls and
/// vectorizes (the same arithmetic; the whole of O = T Bᵀ is formed, its upper triangle kept).
#[inline(always)]
fn sandwich_fixed<const N: usize>(b: &[f64], v: &[f64], out: &mut [f64]) {
    let mut vm = [[0.0f64; N]; N];
    let mut k = 0;
    for j in 0..N {
        for i in 0..=j {
            let x = if i == j { v[k] } else { v[k] / SQ2 };
            vm[j][i] = x;
            vm[i][j] = x;
            k += 1;
        }
    }
    let mut t = [[0.0f64; N]; N];
    for j in 0..N {
        for kk in 0..N {
            let x = vm[j][kk];
            let col: &[f64; N] = b[kk * N..(kk + 1) * N].try_into().expect("N×N");
            for i in 0..N {
                t[j][i] += col[i] * x;
            }
        }
    }
    let mut k = 0;
    for j in 0..N {
        let mut oc = [0.0f64; N];
        for kk in 0..N {
            let x = b[j + kk * N];
            for i in 0..N {
                oc[i] += t[kk][i] * x;
            }
        }
        for (i, o) in oc.iter().enumerate().take(j + 1) {
            out[k] = if i == j { *o } else { o * SQ2 };
            k += 1;
        }
    }
}

/// [`sandwich_fixed`] compiled for AVX2 (without FMA: Rust never fuses a·b + c, so every entry is
/// the same sequence of IEEE products and sums as the baseline build's, the same bits).
///
/// # Safety
/// The processor must have AVX2 ([`wide`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sandwich_avx2<const N: usize>(b: &[f64], v: &[f64], out: &mut [f64]) {
    sandwich_fixed::<N>(b, v, out)
}

#[cfg(not(target_arch = "x86_64"))]
unsafe fn sandwich_avx2<const N: usize>(b: &[f64], v: &[f64], out: &mut [f64]) {
    sandwich_fixed::<N>(b, v, out)
}

/// Whether [`sandwich_avx2`] may run (std caches the detection).
fn wide() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// svec(B V Bᵀ) for V = smat(v), B column-major n×n: two products of n³ and n³/2 multiply–adds
/// on contiguous columns, without allocating (the blocks are at most 16 × 16 in seed 003's
/// programs, where a general matrix product's packing costs more than the product).
pub(super) fn sandwich(b: &[f64], n: usize, v: &[f64], out: &mut [f64], w: &mut Scratch) {
    let wide = wide();
    match n {
        2 => return if wide { unsafe { sandwich_avx2::<2>(b, v, out) } } else { sandwich_fixed::<2>(b, v, out) },
        3 => return if wide { unsafe { sandwich_avx2::<3>(b, v, out) } } else { sandwich_fixed::<3>(b, v, out) },
        4 => return if wide { unsafe { sandwich_avx2::<4>(b, v, out) } } else { sandwich_fixed::<4>(b, v, out) },
        5 => return if wide { unsafe { sandwich_avx2::<5>(b, v, out) } } else { sandwich_fixed::<5>(b, v, out) },
        6 => return if wide { unsafe { sandwich_avx2::<6>(b, v, out) } } else { sandwich_fixed::<6>(b, v, out) },
        7 => return if wide { unsafe { sandwich_avx2::<7>(b, v, out) } } else { sandwich_fixed::<7>(b, v, out) },
        8 => return if wide { unsafe { sandwich_avx2::<8>(b, v, out) } } else { sandwich_fixed::<8>(b, v, out) },
        9 => return if wide { unsafe { sandwich_avx2::<9>(b, v, out) } } else { sandwich_fixed::<9>(b, v, out) },
        10 => return if wide { unsafe { sandwich_avx2::<10>(b, v, out) } } else { sandwich_fixed::<10>(b, v, out) },
        12 => return if wide { unsafe { sandwich_avx2::<12>(b, v, out) } } else { sandwich_fixed::<12>(b, v, out) },
        14 => return if wide { unsafe { sandwich_avx2::<14>(b, v, out) } } else { sandwich_fixed::<14>(b, v, out) },
        16 => return if wide { unsafe { sandwich_avx2::<16>(b, v, out) } } else { sandwich_fixed::<16>(b, v, out) },
        20 => return if wide { unsafe { sandwich_avx2::<20>(b, v, out) } } else { sandwich_fixed::<20>(b, v, out) },
        24 => return if wide { unsafe { sandwich_avx2::<24>(b, v, out) } } else { sandwich_fixed::<24>(b, v, out) },
        28 => return if wide { unsafe { sandwich_avx2::<28>(b, v, out) } } else { sandwich_fixed::<28>(b, v, out) },
        32 => return if wide { unsafe { sandwich_avx2::<32>(b, v, out) } } else { sandwich_fixed::<32>(b, v, out) },
        _ => {}
    }
    let (vm, t, o) = (&mut w.v[..n * n], &mut w.t[..n * n], &mut w.o[..n * n]);
    let mut k = 0;
    for j in 0..n {
        for i in 0..=j {
            let x = if i == j { v[k] } else { v[k] / SQ2 };
            vm[i + j * n] = x;
            vm[j + i * n] = x;
            k += 1;
        }
    }
    // T = B V
    t.iter_mut().for_each(|x| *x = 0.0);
    for j in 0..n {
        for kk in 0..n {
            let x = vm[kk + j * n];
            let (tc, bc) = (&mut t[j * n..(j + 1) * n], &b[kk * n..(kk + 1) * n]);
            tc.iter_mut().zip(bc).for_each(|(t, b)| *t += b * x);
        }
    }
    // O = T Bᵀ, upper triangle only.
    for j in 0..n {
        let oc = &mut o[j * n..j * n + j + 1];
        oc.iter_mut().for_each(|x| *x = 0.0);
        for kk in 0..n {
            let x = b[j + kk * n];
            oc.iter_mut().zip(&t[kk * n..kk * n + j + 1]).for_each(|(o, t)| *o += t * x);
        }
    }
    let mut k = 0;
    for j in 0..n {
        for i in 0..=j {
            out[k] = if i == j { o[i + j * n] } else { o[i + j * n] * SQ2 };
            k += 1;
        }
    }
}
