//! Parameter names, shared between the parameters that spell them alike.
//!
//! A hair file writes the same few names (`type`, `P`, `width0`, `width1`)
//! once per curve, a million times: one shared string per distinct name
//! (a 16-byte pointer in each parameter) instead of a heap block per
//! parameter saves both the memory and the allocation. Names are shared
//! through a small per-thread table; past [`TABLE_LIMIT`] distinct names
//! (a generated or fuzzed file) a name is not added to it (only to the
//! last [`RECENT`] used), so the table stays small whatever the input.

use std::cell::RefCell;
use std::collections::HashSet;
use std::fmt;
use std::hash::{BuildHasherDefault, Hasher};
use std::ops::Deref;
use std::sync::Arc;

/// A parameter's name (`radius` in `"float radius"`): a shared string.
#[derive(Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Name(Arc<str>);

/// Distinct names a thread's table holds at most.
const TABLE_LIMIT: usize = 4096;

/// FNV-1a: names are short, and SipHash's setup would cost more than the
/// allocation the table saves.
#[derive(Default)]
struct Fnv(u64);

impl Hasher for Fnv {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        let mut h = if self.0 == 0 {
            0xcbf2_9ce4_8422_2325
        } else {
            self.0
        };
        for &b in bytes {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
        self.0 = h;
    }
}

/// Names looked up last, compared before the table is: a file's
/// directives mostly repeat a handful (a curve's `type`, `P`, `width`), and
/// a comparison or two costs less than hashing and probing the table.
const RECENT: usize = 8;

/// A thread's names: the table, and the last [`RECENT`] names used.
#[derive(Default)]
struct Names {
    table: HashSet<Arc<str>, BuildHasherDefault<Fnv>>,
    recent: [Option<Arc<str>>; RECENT],
    /// The slot of `recent` the next name takes.
    next: usize,
}

thread_local! {
    static NAMES: RefCell<Names> = RefCell::new(Names::default());
}

impl Name {
    /// The name `text`, shared with earlier names spelt alike.
    pub fn new(text: &str) -> Self {
        NAMES.with(|names| {
            let mut names = names.borrow_mut();
            if let Some(shared) = names.recent.iter().flatten().find(|n| ***n == *text) {
                return Name(shared.clone());
            }
            let name = match names.table.get(text) {
                Some(shared) => shared.clone(),
                None => {
                    let name: Arc<str> = Arc::from(text);
                    if names.table.len() < TABLE_LIMIT {
                        names.table.insert(name.clone());
                    }
                    name
                }
            };
            let slot = names.next;
            names.recent[slot] = Some(name.clone());
            names.next = (slot + 1) % RECENT;
            Name(name)
        })
    }

    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl Default for Name {
    /// The empty name (an unnamed medium, a string parameter left empty).
    fn default() -> Self {
        Name::new("")
    }
}

impl Deref for Name {
    type Target = str;

    fn deref(&self) -> &str {
        &self.0
    }
}

impl AsRef<str> for Name {
    fn as_ref(&self) -> &str {
        &self.0
    }
}

impl From<&str> for Name {
    fn from(text: &str) -> Self {
        Name::new(text)
    }
}

impl From<String> for Name {
    fn from(text: String) -> Self {
        Name::new(&text)
    }
}

impl PartialEq<str> for Name {
    fn eq(&self, other: &str) -> bool {
        &*self.0 == other
    }
}

impl PartialEq<&str> for Name {
    fn eq(&self, other: &&str) -> bool {
        &*self.0 == *other
    }
}

impl PartialEq<String> for Name {
    fn eq(&self, other: &String) -> bool {
        &*self.0 == other.as_str()
    }
}

impl fmt::Display for Name {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl fmt::Debug for Name {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(&*self.0, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_spelt_alike_share_one_string() {
        let a = Name::new("width0");
        let b = Name::new(&String::from("width0"));
        assert!(Arc::ptr_eq(&a.0, &b.0));
        assert_eq!(a, "width0");
        assert_ne!(a, Name::new("width1"));
        assert_eq!(format!("{a} {a:?}"), "width0 \"width0\"");
    }

    #[test]
    fn past_the_table_limit_names_are_still_right() {
        let names: Vec<Name> = (0..TABLE_LIMIT + 10)
            .map(|i| Name::new(&format!("n{i}")))
            .collect();
        for (i, n) in names.iter().enumerate() {
            assert_eq!(*n, format!("n{i}"));
        }
    }
}
