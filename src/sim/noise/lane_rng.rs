//! Every lane's xoshiro256++ stream at once (docs/architecture.md, "Drawing"): the four state
//! words of the block's [`LANES`] streams stored word by word (`s[w][lane]`), so that one step of
//! all streams is a loop over contiguous lanes that the compiler turns into 64-bit vector adds,
//! shifts and xors. Lane l's outputs are exactly those of rand's `Xoshiro256PlusPlus` seeded as
//! trial l's stream ([`super::sampler::trial_rng`]): the vector step and the one-lane step below
//! are the same recurrence, so a lane's numbers never depend on the other lanes or on the path.

use std::convert::Infallible;

use crate::sim::lanes::LANES;

/// The xoshiro256++ state of each lane, word-major.
#[derive(Clone, Debug)]
pub struct LaneRng {
    s: [[u64; LANES]; 4],
}

impl LaneRng {
    /// Every lane seeded (lane l with seed l): lanes a block leaves unused still hold a valid,
    /// never all-zero state, so drawing whole rows stays finite and fast.
    pub fn new() -> Box<Self> {
        let mut r = Box::new(LaneRng { s: [[0; LANES]; 4] });
        for l in 0..LANES {
            r.seed_lane(l, l as u64);
        }
        r
    }

    /// Seeds lane `lane` exactly as rand's `Xoshiro256PlusPlus::seed_from_u64(seed)`: four
    /// successive SplitMix64 outputs (never all zero).
    pub fn seed_lane(&mut self, lane: usize, mut seed: u64) {
        for w in &mut self.s {
            seed = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = seed;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            w[lane] = z ^ (z >> 31);
        }
    }

    /// The next output of every lane (Blackman–Vigna's xoshiro256++ step, lane by lane).
    #[inline(always)]
    pub fn next_row(&mut self, out: &mut [u64; LANES]) {
        for (l, o) in out.iter_mut().enumerate() {
            *o = step(&mut self.s, l);
        }
    }

    /// The next output of lane `lane` alone: the same step as [`LaneRng::next_row`].
    #[inline]
    pub fn next_lane(&mut self, lane: usize) -> u64 {
        step(&mut self.s, lane)
    }

    /// The state of lanes `first..first + W`, word by word, for a run of steps held in registers
    /// (the ziggurat's vector kernels).
    #[inline(always)]
    pub(crate) fn chunk<const W: usize>(&self, first: usize) -> [[u64; W]; 4] {
        std::array::from_fn(|w| self.s[w][first..first + W].try_into().expect("a chunk inside the lanes"))
    }

    /// Stores lanes `first..first + W` back after [`LaneRng::chunk`]'s steps.
    #[inline(always)]
    pub(crate) fn set_chunk<const W: usize>(&mut self, first: usize, c: &[[u64; W]; 4]) {
        for (w, c) in self.s.iter_mut().zip(c) {
            w[first..first + W].copy_from_slice(c);
        }
    }

    /// Lane `lane` as a rand generator, for the draws that stay scalar (other shapes, modes,
    /// factors, joint inputs, the ziggurat's rare slow path).
    pub fn lane(&mut self, lane: usize) -> LaneStream<'_> {
        LaneStream { rng: self, lane }
    }
}

/// One lane of a [`LaneRng`] behind rand's generator traits, with `Xoshiro256PlusPlus`'s
/// conventions (a u32 is the high half of the next u64), so rand's and rand_distr's samplers draw
/// from it exactly what they drew from the lane's own `Xoshiro256PlusPlus`.
pub struct LaneStream<'a> {
    rng: &'a mut LaneRng,
    lane: usize,
}

impl rand::TryRng for LaneStream<'_> {
    type Error = Infallible;

    #[inline]
    fn try_next_u32(&mut self) -> Result<u32, Infallible> {
        Ok((self.rng.next_lane(self.lane) >> 32) as u32)
    }

    #[inline]
    fn try_next_u64(&mut self) -> Result<u64, Infallible> {
        Ok(self.rng.next_lane(self.lane))
    }

    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Infallible> {
        for chunk in dst.chunks_mut(8) {
            let v = self.rng.next_lane(self.lane).to_le_bytes();
            chunk.copy_from_slice(&v[..chunk.len()]);
        }
        Ok(())
    }
}

/// One xoshiro256++ step of lane `l` (Blackman–Vigna): inlined into [`LaneRng::next_row`]'s loop
/// over the lanes, where the state's word-by-word layout lets it compile to vector instructions.
/// The ziggurat's AVX-512 and AVX2 kernels repeat it with intrinsics on a chunk of lanes held in
/// registers ([`LaneRng::chunk`]); tests check them against it lane by lane.
#[inline(always)]
fn step(s: &mut [[u64; LANES]; 4], l: usize) -> u64 {
    let [s0, s1, s2, s3] = s;
    let (a, b, c, d) = (s0[l], s1[l], s2[l], s3[l]);
    let out = a.wrapping_add(d).rotate_left(23).wrapping_add(a);
    let t = b << 17;
    let c = c ^ a;
    let d = d ^ b;
    let b = b ^ c;
    let a = a ^ d;
    s0[l] = a;
    s1[l] = b;
    s2[l] = c ^ t;
    s3[l] = d.rotate_left(45);
    out
}
