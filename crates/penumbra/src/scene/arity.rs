//! Fixed-length arrays read exactly: a vector of 3 numbers given 2 or 4 (or
//! 100,000) is an error saying how many it takes and how many it got, not a
//! value silently cut to size (serde's arrays stop reading at their length).
//!
//! The description's fields keep their plain array types; these functions
//! are their `deserialize_with`.

use std::fmt;
use std::marker::PhantomData;

use serde::de::{Deserialize, Deserializer, Error, IgnoredAny, SeqAccess, Visitor};

/// An array of exactly `N` values.
struct Exact<T, const N: usize>([T; N]);

/// What the elements of an array are called in messages.
trait Named {
    const PLURAL: &'static str;
}

impl Named for f32 {
    const PLURAL: &'static str = "numbers";
}

impl<T, const N: usize> Named for Exact<T, N> {
    const PLURAL: &'static str = "rows";
}

impl<'de, T: Deserialize<'de> + Named, const N: usize> Deserialize<'de> for Exact<T, N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_seq(ExactVisitor::<T, N>(PhantomData))
    }
}

struct ExactVisitor<T, const N: usize>(PhantomData<T>);

impl<'de, T: Deserialize<'de> + Named, const N: usize> Visitor<'de> for ExactVisitor<T, N> {
    type Value = Exact<T, N>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "an array of {N} {}", T::PLURAL)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
        exact_seq(seq).map(Exact)
    }
}

/// Exactly `N` elements from a sequence, or an error with both lengths.
fn exact_seq<'de, A: SeqAccess<'de>, T: Deserialize<'de> + Named, const N: usize>(
    mut seq: A,
) -> Result<[T; N], A::Error> {
    let mut items = Vec::with_capacity(N);
    while items.len() < N {
        match seq.next_element::<T>()? {
            Some(x) => items.push(x),
            None => return Err(wrong_length::<T, A::Error>(N, items.len())),
        }
    }
    // Count the rest without keeping it, to say how many there were.
    let mut got = N;
    while seq.next_element::<IgnoredAny>()?.is_some() {
        got += 1;
    }
    if got != N {
        return Err(wrong_length::<T, A::Error>(N, got));
    }
    items
        .try_into()
        .map_err(|_| wrong_length::<T, A::Error>(N, got))
}

fn wrong_length<T: Named, E: Error>(expected: usize, got: usize) -> E {
    E::custom(format!("expected {expected} {}, got {got}", T::PLURAL))
}

/// Exactly `N` numbers from a sequence being read (for types read by hand,
/// such as a per-axis scale).
pub fn numbers<'de, A: SeqAccess<'de>, const N: usize>(seq: A) -> Result<[f32; N], A::Error> {
    exact_seq::<A, f32, N>(seq)
}

/// `N` numbers, exactly.
pub fn array<'de, D: Deserializer<'de>, const N: usize>(d: D) -> Result<[f32; N], D::Error> {
    Exact::<f32, N>::deserialize(d).map(|e| e.0)
}

/// `N` numbers, exactly, when present.
pub fn option<'de, D: Deserializer<'de>, const N: usize>(
    d: D,
) -> Result<Option<[f32; N]>, D::Error> {
    Option::<Exact<f32, N>>::deserialize(d).map(|o| o.map(|e| e.0))
}

/// An optional 4×4 matrix: exactly 4 rows of exactly 4 numbers.
pub fn matrix<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[[f32; 4]; 4]>, D::Error> {
    Option::<Exact<Exact<f32, 4>, 4>>::deserialize(d).map(|o| o.map(|m| m.0.map(|row| row.0)))
}

#[cfg(test)]
mod tests {
    use serde::Deserialize;

    #[derive(Debug, Deserialize)]
    struct T {
        #[serde(deserialize_with = "super::array", default)]
        v: [f32; 3],
        #[serde(deserialize_with = "super::option", default)]
        o: Option<[f32; 2]>,
        #[serde(deserialize_with = "super::matrix", default)]
        m: Option<[[f32; 4]; 4]>,
    }

    fn err(text: &str) -> String {
        toml::from_str::<T>(text).unwrap_err().message().to_string()
    }

    #[test]
    fn exact_lengths_are_read() {
        let t: T = toml::from_str(
            "v = [1, 2, 3]\no = [4, 5]\nm = [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]",
        )
        .unwrap();
        assert_eq!(t.v, [1.0, 2.0, 3.0]);
        assert_eq!(t.o, Some([4.0, 5.0]));
        assert_eq!(t.m.unwrap()[3], [0.0, 0.0, 0.0, 1.0]);
        let t: T = serde_json::from_str(r#"{"v": [1, 2, 3]}"#).unwrap();
        assert_eq!((t.v, t.o, t.m), ([1.0, 2.0, 3.0], None, None));
    }

    #[test]
    fn too_few_and_too_many_say_both_lengths() {
        assert_eq!(err("v = [1, 2]"), "expected 3 numbers, got 2");
        assert_eq!(err("v = [1, 2, 3, 4]"), "expected 3 numbers, got 4");
        assert_eq!(err("v = []"), "expected 3 numbers, got 0");
        assert_eq!(err("o = [1, 2, 3]"), "expected 2 numbers, got 3");
        let many = vec!["1"; 100_000].join(",");
        assert_eq!(
            err(&format!("v = [{many}]")),
            "expected 3 numbers, got 100000"
        );
        assert_eq!(
            err("m = [[1,0,0,0],[0,1,0,0],[0,0,1,0]]"),
            "expected 4 rows, got 3"
        );
        assert_eq!(
            err("m = [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1,5]]"),
            "expected 4 numbers, got 5"
        );
        let json = serde_json::from_str::<T>(r#"{"v": [1, 2, 3, 4]}"#).unwrap_err();
        assert!(
            json.to_string().starts_with("expected 3 numbers, got 4"),
            "{json}"
        );
    }

    #[test]
    fn wrong_types_are_still_type_errors() {
        assert!(
            err("v = 3").contains("an array of 3 numbers"),
            "{}",
            err("v = 3")
        );
        assert!(err("v = [1, \"x\", 3]").contains("invalid type"));
    }
}
