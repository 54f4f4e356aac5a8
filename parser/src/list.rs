//! A parameter's value list: one value kept inline, more on the heap.
//!
//! Most parameters have one value (`"float width" 0.01`, `"string type"
//! "cylinder"`); a hair file has millions of them. Kept inline, such a
//! value costs no allocation, and a [`List`] is no larger than a boxed
//! slice (16 bytes for numbers and bools: the box's non-null pointer tells
//! the two apart).

use std::fmt;
use std::ops::Deref;

/// A list of values that reads as a slice (`&list[..]`, `list.iter()`).
#[derive(Clone)]
pub struct List<T>(Repr<T>);

#[derive(Clone)]
enum Repr<T> {
    One(T),
    /// Any other count, none included.
    Many(Box<[T]>),
}

impl<T> List<T> {
    /// A list of one value (no allocation).
    pub fn one(value: T) -> Self {
        List(Repr::One(value))
    }

    /// The empty list.
    pub fn empty() -> Self {
        List(Repr::Many(Box::new([])))
    }
}

impl<T> Deref for List<T> {
    type Target = [T];

    fn deref(&self) -> &[T] {
        match &self.0 {
            Repr::One(value) => std::slice::from_ref(value),
            Repr::Many(values) => values,
        }
    }
}

impl<'a, T> IntoIterator for &'a List<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<T> From<Vec<T>> for List<T> {
    fn from(mut values: Vec<T>) -> Self {
        match values.pop() {
            Some(last) if values.is_empty() => List::one(last),
            Some(last) => {
                values.push(last);
                List(Repr::Many(values.into_boxed_slice()))
            }
            None => List::empty(),
        }
    }
}

impl<T: Clone> From<&[T]> for List<T> {
    fn from(values: &[T]) -> Self {
        match values {
            [value] => List::one(value.clone()),
            _ => List(Repr::Many(Box::from(values))),
        }
    }
}

impl<T, const N: usize> From<[T; N]> for List<T> {
    fn from(values: [T; N]) -> Self {
        Vec::from(values).into()
    }
}

impl<T> FromIterator<T> for List<T> {
    fn from_iter<I: IntoIterator<Item = T>>(values: I) -> Self {
        values.into_iter().collect::<Vec<T>>().into()
    }
}

impl<T: PartialEq> PartialEq for List<T> {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

impl<T: fmt::Debug> fmt::Debug for List<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&**self, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_value_is_inline_and_a_list_is_a_slice() {
        assert_eq!(std::mem::size_of::<List<f64>>(), 16);
        let one = List::one(2.5);
        assert!(matches!(one.0, Repr::One(_)));
        assert_eq!(&one[..], &[2.5]);
        assert!(matches!(List::from(vec![1.0]).0, Repr::One(_)));
        let three = List::from([1.0, 2.0, 3.0]);
        assert_eq!(three.len(), 3);
        assert_eq!(three, [1.0, 2.0, 3.0].iter().copied().collect());
        assert!(List::<bool>::empty().is_empty());
        assert_eq!(List::from(Vec::<f64>::new()), List::empty());
    }
}
