//! Every scene under `../shared/scenes/` parses and is described without
//! error, and formatting it (`--format`) gives back the same scene.
//! Skipped, with a message, when `../shared` is absent (a user's clone).

mod common;

use common::{is_absent_include, scene_files, shared_dir};
use pbrt_parser::{Directive, Formatter, Parser};
use rpbrt::scene::{self, SceneBuilder};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Files with no `WorldBegin`: geometry archives meant to be included in
/// the world block, described as such.
fn fragments(files: &[PathBuf]) -> HashSet<PathBuf> {
    files
        .iter()
        .filter(|file| {
            let Ok(parser) = Parser::open(file) else {
                return false;
            };
            !parser
                .follow_includes(false)
                .flatten()
                .any(|d| d.directive == Directive::WorldBegin)
        })
        .map(|f| f.canonicalize().unwrap())
        .collect()
}

fn load(file: &Path, fragment: bool) -> rpbrt::Result<scene::Loaded> {
    if fragment {
        scene::load_fragment(file)
    } else {
        scene::load(file)
    }
}

/// The file's directives, and the same file formatted then parsed again.
fn directives_and_round_trip(file: &Path) -> (Vec<Directive>, String, Vec<Directive>) {
    // pbrt-v3's WorldEnd has no pbrt-v4 text.
    let original: Vec<Directive> = Parser::open(file)
        .unwrap()
        .follow_includes(false)
        .map(|d| d.unwrap().directive)
        .filter(|d| *d != Directive::WorldEnd)
        .collect();
    let mut formatter = Formatter::default();
    let text: String = original.iter().map(|d| formatter.format(d)).collect();
    let again: Vec<Directive> = Parser::from_text(file, text.clone())
        .follow_includes(false)
        .map(|d| {
            d.unwrap_or_else(|e| panic!("formatted {}: {e}", file.display()))
                .directive
        })
        .collect();
    (original, text, again)
}

fn describe_without_includes(file: &Path) -> rpbrt::Result<()> {
    let mut builder = SceneBuilder::new(file.parent().unwrap().to_path_buf());
    let mut last = None;
    for directive in Parser::open(file)?.follow_includes(false) {
        let directive = directive?;
        last = Some(directive.location.clone());
        if !matches!(
            directive.directive,
            Directive::Include(_) | Directive::Import(_)
        ) {
            builder.apply(directive)?;
        }
    }
    builder.finish(&last.unwrap()).map(|_| ())
}

#[test]
fn every_shared_scene_parses_and_builds() {
    let Some(shared) = shared_dir() else { return };
    let files = scene_files(&shared.join("scenes"));
    let fragments = fragments(&files);
    let (mut built, mut absent, mut failures) = (0, Vec::new(), Vec::new());
    for file in &files {
        let fragment = fragments.contains(&file.canonicalize().unwrap());
        match load(file, fragment) {
            Ok(loaded) => {
                built += 1;
                assert!(!loaded.scene.summary().is_empty());
            }
            Err(e) if is_absent_include(&e) => {
                // Still describe the rest of the file (its pbrt-v3 names,
                // materials, camera), with the absent includes left out.
                describe_without_includes(file).unwrap_or_else(|e| {
                    failures.push(format!("{} (includes left out): {e}", file.display()))
                });
                absent.push(format!("{}: {e}", file.display()))
            }
            Err(e) => failures.push(format!("{}: {e}", file.display())),
        }
    }
    eprintln!(
        "{built} of {} shared scene files built; {} skipped because a file they include is absent from ../shared:",
        files.len(),
        absent.len()
    );
    for a in &absent {
        eprintln!("  {}", a.lines().next().unwrap_or(""));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    assert!(built >= 150, "only {built} scene files built");
}

#[test]
fn formatting_round_trips_every_shared_scene() {
    let Some(shared) = shared_dir() else { return };
    let files = scene_files(&shared.join("scenes"));
    let fragments = fragments(&files);
    let mut compared = 0;
    for file in &files {
        let (original, text, again) = directives_and_round_trip(file);
        assert_eq!(
            original.len(),
            again.len(),
            "{}: directive count differs after formatting",
            file.display()
        );
        if let Some(i) = (0..original.len()).find(|&i| original[i] != again[i]) {
            panic!(
                "{}: directive {i} differs after formatting:\n{}\n{}",
                file.display(),
                original[i],
                again[i]
            );
        }
        // Where the whole scene can be described, so must its formatted text.
        let fragment = fragments.contains(&file.canonicalize().unwrap());
        let Ok(expected) = load(file, fragment) else {
            continue;
        };
        let base = file.parent().unwrap().to_path_buf();
        let mut builder = SceneBuilder::new(base);
        if fragment {
            builder.begin_world();
        }
        let formatted = scene::describe(Parser::from_text(file, text), builder)
            .unwrap_or_else(|e| panic!("formatted {}: {e}", file.display()));
        assert!(
            expected.scene == formatted.scene,
            "{}: the formatted scene describes a different scene",
            file.display()
        );
        compared += 1;
    }
    assert!(compared >= 150, "only {compared} descriptions compared");
}
