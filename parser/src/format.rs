//! Canonical pbrt-v4 text for a stream of directives (`--format`,
//! `--upgrade`): one directive per line, one parameter per line, nesting
//! shown by indentation.

use crate::directive::Directive;
use std::fmt;

/// Tracks the indentation of a directive stream.
#[derive(Default)]
pub struct Formatter {
    depth: usize,
}

struct Indented<'a>(&'a Directive, &'a str);

impl fmt::Display for Indented<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.write(f, self.1)
    }
}

impl Formatter {
    /// The text for `directive` (ending in a newline); `None` for
    /// directives that have no pbrt-v4 text (pbrt-v3's WorldEnd).
    pub fn format(&mut self, directive: &Directive) -> Option<String> {
        use Directive as D;
        match directive {
            D::WorldEnd => return None,
            D::AttributeEnd | D::ObjectEnd => {
                self.depth = self.depth.saturating_sub(1)
            }
            _ => {}
        }
        let indent = "    ".repeat(self.depth);
        let mut text = match directive {
            D::WorldBegin => "\nWorldBegin\n".to_string(),
            d => Indented(d, &indent).to_string(),
        };
        text.push('\n');
        if matches!(directive, D::AttributeBegin | D::ObjectBegin(_)) {
            self.depth += 1;
        }
        Some(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Parser;

    #[test]
    fn nesting_is_indented() {
        let mut f = Formatter::default();
        let text: String = Parser::from_text(
            "<f>",
            "WorldBegin AttributeBegin Shape \"sphere\" \"float radius\" 1 AttributeEnd Include \"x.pbrt\"",
        )
        .follow_includes(false)
        .filter_map(|d| f.format(&d.unwrap().directive))
        .collect();
        assert_eq!(
            text,
            "\nWorldBegin\n\nAttributeBegin\n    Shape \"sphere\"\n        \"float radius\" [ 1 ]\nAttributeEnd\nInclude \"x.pbrt\"\n"
        );
    }
}
