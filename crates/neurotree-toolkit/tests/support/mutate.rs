//! A seeded mutation fuzzer on stable Rust: inputs made by mutating seed inputs (corpus
//! files, valid requests) a few edits at a time, fed to a target that must not panic.
//!
//! The number of cases comes from `NEUROTREE_FUZZ_CASES` (a few thousand per target by
//! default, so that `cargo test` stays quick), the random seed from `NEUROTREE_FUZZ_SEED`
//! (fixed by default, so that a plain run is the same every time). A case that panics is
//! saved to a file in the temporary directory, named in the failure.

use std::panic::{catch_unwind, AssertUnwindSafe};

/// The cases a target runs: `NEUROTREE_FUZZ_CASES`, else `default`.
pub fn cases(default: usize) -> usize {
    match std::env::var("NEUROTREE_FUZZ_CASES") {
        Ok(text) => text
            .parse()
            .unwrap_or_else(|_| panic!("NEUROTREE_FUZZ_CASES={text:?} is not a number")),
        Err(_) => default,
    }
}

/// The random seed: `NEUROTREE_FUZZ_SEED`, else a fixed one.
pub fn seed() -> u64 {
    match std::env::var("NEUROTREE_FUZZ_SEED") {
        Ok(text) => text
            .parse()
            .unwrap_or_else(|_| panic!("NEUROTREE_FUZZ_SEED={text:?} is not a number")),
        Err(_) => 0x6e65_7572_6f74_7265,
    }
}

/// SplitMix64: small, fast and good enough to pick edits.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

/// Bytes that often matter to parsers of text: delimiters, quotes, the ends of lines, a
/// NUL, a byte that is never UTF-8.
const SPECIAL_BYTES: &[u8] = b"<>/\"'={}&;:()[]!?-+*_@$ \n\r\t\x000\xff";

/// Makes inputs from `seeds` by 1 to 8 edits: bit flips, bytes set, dictionary tokens
/// inserted, ranges deleted, repeated, spliced from another seed, and cuts.
pub struct Mutator<'a> {
    rng: Rng,
    seeds: &'a [Vec<u8>],
    dictionary: &'a [&'a [u8]],
}

impl<'a> Mutator<'a> {
    pub fn new(rng: Rng, seeds: &'a [Vec<u8>], dictionary: &'a [&'a [u8]]) -> Self {
        assert!(!seeds.is_empty(), "a mutation fuzzer needs seeds");
        Mutator {
            rng,
            seeds,
            dictionary,
        }
    }

    pub fn input(&mut self) -> Vec<u8> {
        let mut input = self.seeds[self.rng.below(self.seeds.len())].clone();
        for _ in 0..1 + self.rng.below(8) {
            self.edit(&mut input);
        }
        input
    }

    /// A range of `input`, up to 32 bytes long.
    fn range(&mut self, len: usize) -> std::ops::Range<usize> {
        let start = self.rng.below(len + 1);
        let end = (start + self.rng.below(33)).min(len);
        start..end
    }

    fn edit(&mut self, input: &mut Vec<u8>) {
        let len = input.len();
        let at = self.rng.below(len + 1);
        match self.rng.below(8) {
            0 if at < len => input[at] ^= 1 << self.rng.below(8),
            1 if at < len => input[at] = self.rng.next() as u8,
            2 if at < len => input[at] = SPECIAL_BYTES[self.rng.below(SPECIAL_BYTES.len())],
            3 if !self.dictionary.is_empty() => {
                let token = self.dictionary[self.rng.below(self.dictionary.len())];
                input.splice(at..at, token.iter().copied());
            }
            4 => {
                input.drain(self.range(len));
            }
            5 => {
                let copied = input[self.range(len)].to_vec();
                input.splice(at..at, copied);
            }
            6 => {
                let other = &self.seeds[self.rng.below(self.seeds.len())];
                let from = {
                    let start = self.rng.below(other.len() + 1);
                    start..(start + self.rng.below(65)).min(other.len())
                };
                let replaced = self.range(len);
                input.splice(replaced, other[from].iter().copied());
            }
            _ => input.truncate(at),
        }
    }
}

/// Runs `target` on every seed, then on `cases` mutated inputs. A panic fails the test
/// naming the case, the seed and the file the input was saved to.
pub fn fuzz(
    name: &str,
    default_cases: usize,
    seeds: &[Vec<u8>],
    dictionary: &[&[u8]],
    target: impl Fn(&[u8]),
) {
    let (cases, seed) = (cases(default_cases), seed());
    let run = |case: &str, input: &[u8]| {
        if catch_unwind(AssertUnwindSafe(|| target(input))).is_err() {
            let file = std::env::temp_dir().join(format!("neurotree-fuzz-{name}-{seed}-{case}"));
            let saved = match std::fs::write(&file, input) {
                Ok(()) => format!("saved to {}", file.display()),
                Err(e) => format!("not saved: {e}"),
            };
            panic!("{name}: {case} (NEUROTREE_FUZZ_SEED={seed}) panicked; its input is {saved}");
        }
    };
    for (i, input) in seeds.iter().enumerate() {
        run(&format!("seed{i}"), input);
    }
    let mut mutator = Mutator::new(Rng::new(seed), seeds, dictionary);
    for case in 0..cases {
        run(&format!("case{case}"), &mutator.input());
    }
    eprintln!(
        "{name}: {} seeds and {cases} mutated cases, seed {seed}",
        seeds.len()
    );
}
