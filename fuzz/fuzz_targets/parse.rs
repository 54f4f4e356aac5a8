//! Any bytes: the parser and the scene builder either succeed or give an
//! error; they never panic, hang or allocate without bound.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pbrt_parser::{Directive, Formatter, Parser};
use rpbrt::scene::SceneBuilder;

fuzz_target!(|data: &[u8]| {
    // Includes are not followed: a fuzzed path could name any file.
    let parser = Parser::from_text("fuzz.pbrt", data.to_vec()).follow_includes(false);
    let mut builder = SceneBuilder::new(std::path::PathBuf::new());
    let mut formatter = Formatter::default();
    let mut last = None;
    for directive in parser {
        let Ok(directive) = directive else {
            // Errors must print (line:col computed from the text).
            let _ = directive.map_err(|e| e.to_string());
            return;
        };
        // Formatting must not panic either.
        let _ = formatter.format(&directive.directive);
        last = Some(directive.location.clone());
        if matches!(directive.directive, Directive::Include(_) | Directive::Import(_)) {
            continue;
        }
        if let Err(e) = builder.apply(directive) {
            let _ = e.to_string();
            return;
        }
    }
    if let Some(end) = last {
        if let Ok((scene, _)) = builder.finish(&end) {
            let _ = scene.summary();
        }
    }
});
