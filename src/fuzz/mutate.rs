//! A seeded byte mutator over a corpus (stacked flips, inserts, deletions, duplications, splices with other
//! corpus files, numbers swapped for edge values): no coverage feedback, which stable Rust does not give,
//! but the shipped files as seeds keep most inputs close to valid so the checks past the parser run.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Inputs grow no larger than this.
const MAX_LEN: usize = 64 * 1024;

/// Edge values and syntax that parsers get wrong.
const TOKENS: &[&[u8]] = &[
    b"nan",
    b"inf",
    b"-inf",
    b"+inf",
    b"-nan",
    b"1e309",
    b"-1e309",
    b"1e-320",
    b"-1",
    b"0",
    b"-0.0",
    b"4294967296",
    b"18446744073709551616",
    b"-9223372036854775809",
    b"9e9",
    b"214.0",
    b"-91",
    b"\xff",
    b"\xc3",
    b"\xe2\x82",
    b"\0",
    b"\"",
    b"'",
    b"\\",
    b"[",
    b"]",
    b"{",
    b"}",
    b"=",
    b"\n",
    b"\r\n",
    b"\t",
    b".",
    b"..",
    b",",
    b";",
    b":",
    b"(",
    b")",
    b"-oo",
    b"+oo",
    b"oo",
    b"true",
    b"false",
    b"[[",
    b"]]",
    b"\"\"\"",
    b"#",
    b"null",
    b"1.5",
    b"0.0",
    b"65535",
    b"65536",
    b"256",
];

/// Writes into `out` a mutation of `base`, drawing splices from `corpus`.
pub fn mutate(rng: &mut ChaCha8Rng, base: &[u8], corpus: &[Vec<u8>], out: &mut Vec<u8>) {
    out.clear();
    out.extend_from_slice(base);
    let rounds = 1 + rng.gen_range(0..8u32).min(rng.gen_range(0..8u32));
    for _ in 0..rounds {
        one(rng, corpus, out);
        out.truncate(MAX_LEN);
    }
}

fn pos(rng: &mut ChaCha8Rng, v: &[u8]) -> usize {
    rng.gen_range(0..=v.len())
}

/// A range of `v`, mostly short.
fn range(rng: &mut ChaCha8Rng, v: &[u8]) -> (usize, usize) {
    let a = pos(rng, v);
    let len = rng.gen_range(0..=16usize.min(v.len() - a));
    let len = if rng.gen_bool(0.1) { v.len() - a } else { len };
    (a, a + len)
}

fn one(rng: &mut ChaCha8Rng, corpus: &[Vec<u8>], v: &mut Vec<u8>) {
    match rng.gen_range(0..10u32) {
        0 if !v.is_empty() => {
            let i = rng.gen_range(0..v.len());
            v[i] ^= 1 << rng.gen_range(0..8u32);
        }
        1 if !v.is_empty() => {
            let i = rng.gen_range(0..v.len());
            v[i] = rng.gen();
        }
        2 | 3 => {
            let t = TOKENS[rng.gen_range(0..TOKENS.len())];
            let at = pos(rng, v);
            v.splice(at..at, t.iter().copied());
        }
        4 => {
            let (a, b) = range(rng, v);
            v.drain(a..b);
        }
        5 => {
            let (a, b) = range(rng, v);
            let chunk = v[a..b].to_vec();
            let at = pos(rng, v);
            v.splice(at..at, chunk);
        }
        6 if !corpus.is_empty() => {
            let other = &corpus[rng.gen_range(0..corpus.len())];
            let (a, b) = range(rng, other);
            let (c, d) = range(rng, v);
            v.splice(c..d, other[a..b].iter().copied());
        }
        7 => replace_number(rng, v),
        8 => {
            // A whole value swapped for an edge token: after `=` or `:` or at a word boundary.
            let t = TOKENS[rng.gen_range(0..TOKENS.len())];
            let (a, b) = range(rng, v);
            v.splice(a..b, t.iter().copied());
        }
        _ => {
            let at = pos(rng, v);
            v.truncate(at.max(v.len().saturating_sub(rng.gen_range(0..64))));
        }
    }
}

/// Replaces one run of digits (with its sign and fraction) by an edge value.
fn replace_number(rng: &mut ChaCha8Rng, v: &mut Vec<u8>) {
    let starts: Vec<usize> = (0..v.len())
        .filter(|&i| v[i].is_ascii_digit() && (i == 0 || !v[i - 1].is_ascii_digit()))
        .collect();
    if starts.is_empty() {
        return;
    }
    let a = starts[rng.gen_range(0..starts.len())];
    let b = a + v[a..]
        .iter()
        .take_while(|c| c.is_ascii_digit() || **c == b'.' || **c == b'e')
        .count();
    let t = TOKENS[rng.gen_range(0..22)];
    v.splice(a..b, t.iter().copied());
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn the_same_seed_gives_the_same_mutations() {
        let corpus = vec![b"speed = 1.5\n[a]\nx = [1, 2]\n".to_vec()];
        let run = |seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut out = Vec::new();
            (0..50)
                .map(|_| {
                    mutate(&mut rng, &corpus[0], &corpus, &mut out);
                    out.clone()
                })
                .collect::<Vec<_>>()
        };
        assert_eq!(run(7), run(7));
        assert!(run(7).iter().any(|m| m != &corpus[0]), "mutates");
        assert!(run(7).iter().all(|m| m.len() <= MAX_LEN));
    }
}
