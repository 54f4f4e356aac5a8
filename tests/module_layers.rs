//! Imports run one way: no cycle between the `rpbrt` crate's top-level
//! modules, nor between the files of one folder; the same for the
//! benchmark harness's crate (`bench/`).
//!
//! Reads every `src/**/*.rs` file, finds the paths it names (`crate::…`,
//! `super::…`, `self::…`, grouped `use crate::{a::…, b::…}` included) in
//! its code (comments, strings and `#[cfg(test)]` items left out: a test
//! may load a scene through the layer above), and builds two graphs:
//! - top-level modules (`src/scene/` → `scene`, `src/error.rs` → `error`):
//!   an edge where a file of one names the other;
//! - for each folder, its files and subfolders: an edge where one names a
//!   sibling. A folder's `mod.rs` is its interface (its children use the
//!   types it declares, and it re-exports them), so it takes no part.
//!
//! Each strongly connected component of more than one node is a cycle,
//! printed with the files that make each of its edges. Edges that cannot
//! be removed yet are listed in [`ALLOWED`] with the reason; an entry no
//! longer needed is an error too, so the list only shrinks.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Import edges tolerated for now, as (from, to) node names (top-level
/// module names, or folder-relative file paths such as
/// `src/shapes/curve.rs`), each with why.
const ALLOWED: &[(&str, &str, &str)] = &[
    // Empty: every cycle the checker found has been ended. An entry is
    // (from, to, why), for a cycle that must stay for a stated reason.
];

/// A module's path from the crate root, e.g. `["shapes", "curve"]`.
type ModulePath = Vec<String>;

/// Replaces comments, string literals and character literals by spaces
/// (keeping line lengths), so that only code is searched.
fn mask(source: &str) -> String {
    let bytes = source.as_bytes();
    let mut out = bytes.to_vec();
    let blank = |out: &mut Vec<u8>, from: usize, to: usize| {
        for b in &mut out[from..to] {
            if *b != b'\n' {
                *b = b' ';
            }
        }
    };
    let mut i = 0;
    while i < bytes.len() {
        let rest = &bytes[i..];
        if rest.starts_with(b"//") {
            let end = rest
                .iter()
                .position(|&b| b == b'\n')
                .map_or(bytes.len(), |n| i + n);
            blank(&mut out, i, end);
            i = end;
        } else if rest.starts_with(b"/*") {
            let mut depth = 0;
            let mut j = i;
            while j < bytes.len() {
                if bytes[j..].starts_with(b"/*") {
                    depth += 1;
                    j += 2;
                } else if bytes[j..].starts_with(b"*/") {
                    depth -= 1;
                    j += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    j += 1;
                }
            }
            blank(&mut out, i, j);
            i = j;
        } else if (rest.starts_with(b"r\"") || rest.starts_with(b"r#"))
            && (i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_'))
        {
            // A raw string: r"…", r#"…"#, …
            let hashes = rest[1..].iter().take_while(|&&b| b == b'#').count();
            if rest.get(1 + hashes) != Some(&b'"') {
                i += 1;
                continue;
            }
            let mut closing = vec![b'"'];
            closing.extend(std::iter::repeat_n(b'#', hashes));
            let start = i + 2 + hashes;
            let end = bytes[start..]
                .windows(closing.len())
                .position(|w| w == closing.as_slice())
                .map_or(bytes.len(), |n| start + n + closing.len());
            blank(&mut out, i, end);
            i = end;
        } else if rest[0] == b'"' {
            let mut j = i + 1;
            while j < bytes.len() && bytes[j] != b'"' {
                j += if bytes[j] == b'\\' { 2 } else { 1 };
            }
            let end = (j + 1).min(bytes.len());
            blank(&mut out, i, end);
            i = end;
        } else if rest[0] == b'\'' {
            // A character literal ('x', '\n', '\u{..}', 'é'), or a lifetime.
            let literal_end = if rest.get(1) == Some(&b'\\') {
                rest[2..]
                    .iter()
                    .position(|&b| b == b'\'')
                    .map(|n| i + 3 + n)
            } else {
                let next_char = source[i + 1..].chars().next().map_or(1, char::len_utf8);
                (rest.get(1 + next_char) == Some(&b'\'')).then_some(i + 2 + next_char)
            };
            match literal_end {
                Some(end) => {
                    blank(&mut out, i, end);
                    i = end;
                }
                None => i += 1,
            }
        } else {
            i += 1;
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The byte just past the `}` matching the `{` at `open` (in masked text).
fn matching_brace(text: &str, open: usize) -> usize {
    let mut depth = 0usize;
    for (i, b) in text.bytes().enumerate().skip(open) {
        match b {
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return i + 1;
                }
            }
            _ => {}
        }
    }
    text.len()
}

/// Masked text without its `#[cfg(test)]` items, and the names of the
/// test-only child modules it declares (`#[cfg(test)] mod tests;`).
fn without_tests(masked: &str) -> (String, Vec<String>) {
    const ATTRIBUTE: &str = "#[cfg(test)]";
    let mut kept = String::new();
    let mut test_modules = Vec::new();
    let mut rest = masked;
    while let Some(at) = rest.find(ATTRIBUTE) {
        kept.push_str(&rest[..at]);
        let after = &rest[at + ATTRIBUTE.len()..];
        let Some(stop) = after.find([';', '{']) else {
            rest = "";
            break;
        };
        let end = if after.as_bytes()[stop] == b';' {
            let item: Vec<&str> = after[..stop].split_whitespace().collect();
            if let Some(position) = item.iter().position(|w| *w == "mod") {
                if let Some(name) = item.get(position + 1) {
                    test_modules.push(name.to_string());
                }
            }
            stop + 1
        } else {
            matching_brace(after, stop)
        };
        rest = &after[end..];
    }
    kept.push_str(rest);
    (kept, test_modules)
}

fn is_identifier_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// The paths named in (masked) code, resolved from `module` to paths from
/// the crate root: `crate::a::b`, `super::b`, `self::b`, and each item of
/// a group `crate::{a::b, c}`. Only the path's leading identifiers are
/// kept (enough to find the module).
fn named_paths(code: &str, module: &[String]) -> Vec<ModulePath> {
    let bytes = code.as_bytes();
    let mut paths = Vec::new();
    for start in ["crate::", "super::", "self::"] {
        let mut from = 0;
        while let Some(found) = code[from..].find(start) {
            let at = from + found;
            from = at + start.len();
            if at > 0 && (is_identifier_byte(bytes[at - 1]) || bytes[at - 1] == b':') {
                continue; // `foo::super::` is not a path start we resolve
            }
            // Leading `super::super::…`.
            let mut base: Vec<String> = match start {
                "crate::" => Vec::new(),
                "self::" => module.to_vec(),
                _ => module[..module.len().saturating_sub(1)].to_vec(),
            };
            let mut cursor = at + start.len();
            while code[cursor..].starts_with("super::") {
                base.pop();
                cursor += "super::".len();
            }
            for tail in path_tails(code, cursor) {
                let mut path = base.clone();
                path.extend(tail);
                paths.push(path);
            }
        }
    }
    paths
}

/// The identifier sequences that follow a path prefix ending at `cursor`:
/// one (`a::b::C`), or one per item of a group (`{a::b, c::{d, e}}`).
fn path_tails(code: &str, cursor: usize) -> Vec<Vec<String>> {
    let bytes = code.as_bytes();
    let skip_space = |mut i: usize| {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        i
    };
    let cursor = skip_space(cursor);
    if bytes.get(cursor) == Some(&b'{') {
        let end = matching_brace(code, cursor);
        let inner = &code[cursor + 1..end.saturating_sub(1)];
        // Split the group's items at its top-level commas.
        let mut items = Vec::new();
        let (mut depth, mut item_start) = (0usize, 0usize);
        for (i, b) in inner.bytes().enumerate() {
            match b {
                b'{' => depth += 1,
                b'}' => depth -= 1,
                b',' if depth == 0 => {
                    items.push(item_start);
                    item_start = i + 1;
                }
                _ => {}
            }
        }
        items.push(item_start);
        return items
            .into_iter()
            .flat_map(|item| {
                path_tails(code, cursor + 1 + item)
                    .into_iter()
                    .filter(|tail| !tail.is_empty())
            })
            .collect();
    }
    let mut tail = Vec::new();
    let mut i = cursor;
    loop {
        let start = i;
        while i < bytes.len() && is_identifier_byte(bytes[i]) {
            i += 1;
        }
        if i == start {
            break;
        }
        tail.push(code[start..i].to_string());
        if !code[i..].starts_with("::") {
            break;
        }
        i += 2;
        if bytes.get(i) == Some(&b'{') {
            // `a::{b, c}`: the group's items follow `a`.
            return path_tails(code, i)
                .into_iter()
                .map(|rest| tail.iter().cloned().chain(rest).collect())
                .collect();
        }
    }
    vec![tail]
}

/// One source file: its module path, and the paths its non-test code
/// names.
struct SourceFile {
    /// Relative to the crate root, e.g. `src/shapes/curve.rs`.
    name: String,
    module: ModulePath,
    named: Vec<ModulePath>,
}

/// Every `.rs` file under `folder`, sorted.
fn rust_files(folder: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![folder.to_path_buf()];
    while let Some(dir) = pending.pop() {
        let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        for entry in entries {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// Reads the crate's source files (leaving out test-only files).
fn read_crate(root: &Path) -> Vec<SourceFile> {
    let src = root.join("src");
    let mut files = Vec::new();
    let mut test_only = BTreeSet::new();
    for path in rust_files(&src) {
        let relative = path.strip_prefix(&src).expect("under src");
        let mut module: ModulePath = relative
            .iter()
            .map(|c| c.to_string_lossy().trim_end_matches(".rs").to_string())
            .collect();
        let is_folder_interface = matches!(
            module.last().map(String::as_str),
            Some("mod" | "lib" | "main")
        );
        if is_folder_interface {
            module.pop();
        }
        let text = std::fs::read_to_string(&path).expect("a readable source file");
        let (code, test_modules) = without_tests(&mask(&text));
        let folder = path.parent().expect("a folder");
        // `#[cfg(test)] mod name;` in `x.rs` declares `x/name.rs`; in
        // `mod.rs` (or the crate root), `name.rs` beside it.
        let child_folder = if is_folder_interface {
            folder.to_path_buf()
        } else {
            folder.join(path.file_stem().expect("a file name"))
        };
        for name in test_modules {
            test_only.insert(child_folder.join(format!("{name}.rs")));
            test_only.insert(child_folder.join(&name).join("mod.rs"));
        }
        files.push((path, module, code));
    }
    files
        .into_iter()
        .filter(|(path, _, _)| !test_only.contains(path))
        .filter(|(path, _, _)| path.file_name().is_some_and(|n| n != "main.rs"))
        .map(|(path, module, code)| SourceFile {
            name: path
                .strip_prefix(root)
                .expect("under the root")
                .display()
                .to_string(),
            named: named_paths(&code, &module),
            module,
        })
        .collect()
}

/// A directed graph: node → (node it names → files that make the edge).
type Graph = BTreeMap<String, BTreeMap<String, BTreeSet<String>>>;

fn add_edge(graph: &mut Graph, from: &str, to: &str, file: &str) {
    graph.entry(to.to_string()).or_default();
    graph
        .entry(from.to_string())
        .or_default()
        .entry(to.to_string())
        .or_default()
        .insert(file.to_string());
}

/// The top-level module graph, and one graph per folder over its files
/// and subfolders (keyed by folder).
fn module_graphs(files: &[SourceFile]) -> (Graph, BTreeMap<String, Graph>) {
    // What each folder holds (a child is a file or a subfolder).
    let mut children: BTreeMap<ModulePath, BTreeSet<String>> = BTreeMap::new();
    for file in files {
        if let Some((last, parent)) = file.module.split_last() {
            children
                .entry(parent.to_vec())
                .or_default()
                .insert(last.clone());
        }
    }
    let top_level = children.get(&Vec::new()).cloned().unwrap_or_default();
    let mut modules = Graph::new();
    let mut folders: BTreeMap<String, Graph> = BTreeMap::new();
    for file in files {
        let Some(own_top) = file.module.first() else {
            continue; // the crate root declares the modules
        };
        for path in &file.named {
            if let Some(top) = path.first() {
                if top != own_top && top_level.contains(top) {
                    add_edge(&mut modules, own_top, top, &file.name);
                }
            }
            // A sibling at each level of the file's folders: in folder
            // `module[..level]`, the file belongs to child `module[level]`
            // (a file, or the subfolder it is in; a folder's `mod.rs` is
            // its folder's, so takes no part in its own folder's graph).
            for level in 1..file.module.len() {
                let (parent, own) = (&file.module[..level], &file.module[level]);
                let Some(siblings) = children.get(parent) else {
                    continue;
                };
                if path.len() <= level || path[..level] != *parent {
                    continue;
                }
                let sibling = &path[level];
                if sibling == own || !siblings.contains(sibling) {
                    continue;
                }
                let folder = format!("src/{}", parent.join("/"));
                let node = |name: &str| {
                    let mut child = parent.to_vec();
                    child.push(name.to_string());
                    if children.contains_key(&child) {
                        format!("{folder}/{name}/")
                    } else {
                        format!("{folder}/{name}.rs")
                    }
                };
                add_edge(
                    folders.entry(folder.clone()).or_default(),
                    &node(own),
                    &node(sibling),
                    &file.name,
                );
            }
        }
    }
    (modules, folders)
}

/// The strongly connected components of more than one node (Tarjan).
fn cycles(graph: &Graph) -> Vec<Vec<String>> {
    struct State<'g> {
        graph: &'g Graph,
        index: BTreeMap<&'g str, usize>,
        low: BTreeMap<&'g str, usize>,
        stack: Vec<&'g str>,
        on_stack: BTreeSet<&'g str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'g>(state: &mut State<'g>, node: &'g str) {
        let next = state.index.len();
        state.index.insert(node, next);
        state.low.insert(node, next);
        state.stack.push(node);
        state.on_stack.insert(node);
        let graph = state.graph;
        for to in graph.get(node).into_iter().flat_map(|edges| edges.keys()) {
            if !state.index.contains_key(to.as_str()) {
                visit(state, to);
                let low = state.low[to.as_str()].min(state.low[node]);
                state.low.insert(node, low);
            } else if state.on_stack.contains(to.as_str()) {
                let low = state.index[to.as_str()].min(state.low[node]);
                state.low.insert(node, low);
            }
        }
        if state.low[node] == state.index[node] {
            let mut component = Vec::new();
            while let Some(top) = state.stack.pop() {
                state.on_stack.remove(top);
                component.push(top.to_string());
                if top == node {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort();
                state.found.push(component);
            }
        }
    }
    let mut state = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for node in graph.keys() {
        if !state.index.contains_key(node.as_str()) {
            visit(&mut state, node);
        }
    }
    state.found
}

/// One cycle through the component's first node (a shortest one, by a
/// breadth-first search), e.g. `a → b → a`.
fn example_cycle(graph: &Graph, component: &[String]) -> String {
    let start = &component[0];
    let inside: BTreeSet<&String> = component.iter().collect();
    let mut came_from: BTreeMap<&String, &String> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([start]);
    while let Some(node) = queue.pop_front() {
        for to in graph[node].keys().filter(|to| inside.contains(to)) {
            if to == start {
                let mut path = vec![start.as_str()];
                let mut at = node;
                while at != start {
                    path.push(at);
                    at = came_from[at];
                }
                path.push(start);
                path.reverse();
                return path.join(" → ");
            }
            if !came_from.contains_key(to) {
                came_from.insert(to, node);
                queue.push_back(to);
            }
        }
    }
    component.join(", ")
}

/// A report of every cycle of `graph` (empty if none), after removing the
/// allowed edges.
fn describe_cycles(mut graph: Graph, allowed: &[(&str, &str, &str)]) -> String {
    for (from, to, _) in allowed {
        if let Some(edges) = graph.get_mut(*from) {
            edges.remove(*to);
        }
    }
    let mut report = String::new();
    for component in cycles(&graph) {
        let _ = writeln!(
            report,
            "import cycle: {}",
            example_cycle(&graph, &component)
        );
        for from in &component {
            for (to, files) in &graph[from] {
                if component.contains(to) {
                    let files: Vec<&str> = files.iter().map(String::as_str).collect();
                    let _ = writeln!(report, "    {from} → {to}: {}", files.join(", "));
                }
            }
        }
    }
    report
}

fn crate_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn no_import_cycle_between_top_level_modules_or_sibling_files() {
    check_crate(&crate_root(), 50, ALLOWED);
}

/// The same for the benchmark harness's crate (`bench/`).
#[test]
fn no_import_cycle_in_the_benchmark_harness() {
    check_crate(&crate_root().join("bench"), 5, &[]);
}

/// Fails with the cycles (but those `allowed`) of the crate at `root`,
/// which must have more than `at_least` source files, and with each
/// allowed edge that is gone.
fn check_crate(root: &Path, at_least: usize, allowed: &[(&str, &str, &str)]) {
    let files = read_crate(root);
    assert!(
        files.len() > at_least,
        "{}: found only {} source files",
        root.display(),
        files.len()
    );
    let (modules, folders) = module_graphs(&files);
    let mut report = describe_cycles(modules.clone(), allowed);
    for graph in folders.values() {
        report.push_str(&describe_cycles(graph.clone(), allowed));
    }
    // Allowed edges that no longer exist: remove them from the list.
    for (from, to, _) in allowed {
        let exists = |graph: &Graph| {
            graph
                .get(*from)
                .is_some_and(|edges| edges.contains_key(*to))
        };
        if !exists(&modules) && !folders.values().any(exists) {
            let _ = writeln!(
                report,
                "allowed edge {from} → {to} is gone: remove it from ALLOWED"
            );
        }
    }
    assert!(report.is_empty(), "\n{report}");
}

/// A graph from `(from, to)` pairs.
fn graph_of(edges: &[(&str, &str)]) -> Graph {
    let mut graph = Graph::new();
    for (from, to) in edges {
        add_edge(&mut graph, from, to, "synthetic.rs");
    }
    graph
}

#[test]
fn the_checker_finds_a_cycle_and_only_a_cycle() {
    let acyclic = graph_of(&[("a", "b"), ("b", "c"), ("a", "c"), ("c", "d")]);
    assert!(cycles(&acyclic).is_empty());
    assert_eq!(describe_cycles(acyclic, &[]), "");

    let cyclic = graph_of(&[
        ("a", "b"),
        ("b", "c"),
        ("c", "a"),
        ("c", "d"),
        ("d", "e"),
        ("e", "d"),
    ]);
    let found = cycles(&cyclic);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found.contains(&vec!["a".to_string(), "b".to_string(), "c".to_string()]));
    assert!(found.contains(&vec!["d".to_string(), "e".to_string()]));
    let report = describe_cycles(cyclic.clone(), &[]);
    assert!(report.contains("import cycle: a → b → c → a"), "{report}");
    assert!(report.contains("d → e: synthetic.rs"), "{report}");
    // An allowed edge breaks its cycle, and only its own.
    let report = describe_cycles(cyclic, &[("e", "d", "synthetic")]);
    assert!(!report.contains("d → e"), "{report}");
    assert!(report.contains("a → b → c → a"), "{report}");
}

#[test]
fn the_checker_reads_paths_in_code_only() {
    let source = r##"
//! Links to [`crate::docs_only`].
use crate::math::{Ray, frame::{Frame, Basis}, hash};
use super::sibling::Thing;
use super::super::grand::Other;
const NOT_A_PATH: &str = "crate::in_a_string";
const RAW: &str = r#"crate::in_a_raw_string"#;
fn f<'a>(x: &'a str) -> char { let _ = crate::spectrum::Spectrum::new(); '{' }
/* crate::in_a_block_comment */
#[cfg(test)]
mod tests {
    use crate::scene::load_text;
    fn g() { let _ = "}"; }
}
#[cfg(test)]
mod test_support;
fn after() { self::own_child::h(); }
"##;
    let (code, test_modules) = without_tests(&mask(source));
    assert_eq!(test_modules, ["test_support"]);
    let module: ModulePath = vec!["shapes".into(), "curve".into(), "inner".into()];
    let named: BTreeSet<String> = named_paths(&code, &module)
        .into_iter()
        .map(|p| p.join("::"))
        .collect();
    let expected: BTreeSet<String> = [
        "math::Ray",
        "math::frame::Frame",
        "math::frame::Basis",
        "math::hash",
        "spectrum::Spectrum::new",
        "shapes::curve::sibling::Thing",
        "shapes::grand::Other",
        "shapes::curve::inner::own_child::h",
    ]
    .into_iter()
    .map(String::from)
    .collect();
    assert_eq!(named, expected);
}

#[test]
fn the_checker_finds_a_cycle_between_sibling_files_and_between_modules() {
    let file = |name: &str, module: &[&str], named: &[&[&str]]| SourceFile {
        name: name.to_string(),
        module: module.iter().map(|s| s.to_string()).collect(),
        named: named
            .iter()
            .map(|p| p.iter().map(|s| s.to_string()).collect())
            .collect(),
    };
    let files = [
        file(
            "src/shapes/mod.rs",
            &["shapes"],
            &[&["shapes", "curve", "Curve"]],
        ),
        file(
            "src/shapes/curve.rs",
            &["shapes", "curve"],
            &[&["shapes", "frame", "f"], &["scene", "x"]],
        ),
        file(
            "src/shapes/frame.rs",
            &["shapes", "frame"],
            &[&["shapes", "curve", "g"], &["shapes", "Shape"]],
        ),
        file("src/scene/mod.rs", &["scene"], &[&["shapes", "Shape"]]),
    ];
    let (modules, folders) = module_graphs(&files);
    let report = describe_cycles(modules, &[]);
    assert!(
        report.contains("scene → shapes: src/scene/mod.rs"),
        "{report}"
    );
    assert!(
        report.contains("shapes → scene: src/shapes/curve.rs"),
        "{report}"
    );
    let report = describe_cycles(folders["src/shapes"].clone(), &[]);
    assert!(
        report.contains(
            "import cycle: src/shapes/curve.rs → src/shapes/frame.rs → src/shapes/curve.rs"
        ),
        "{report}"
    );
}
