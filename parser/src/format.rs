//! Canonical pbrt-v4 text for a stream of directives (`--format`,
//! `--upgrade`): one directive per line, one parameter per line, nesting
//! shown by indentation.

use crate::directive::Directive;

/// Tracks the indentation of a directive stream.
#[derive(Default)]
pub struct Formatter {
    depth: usize,
    indent: String,
}

impl Formatter {
    /// Appends the text for `directive` (ending in a newline) to `out`;
    /// directives that have no pbrt-v4 text (pbrt-v3's WorldEnd) add nothing.
    pub fn write(&mut self, directive: &Directive, out: &mut String) {
        use Directive as D;
        match directive {
            D::WorldEnd => return,
            D::AttributeEnd | D::ObjectEnd => self.set_depth(self.depth.saturating_sub(1)),
            _ => {}
        }
        match directive {
            D::WorldBegin => out.push_str("\nWorldBegin\n"),
            d => d.write_to(out, &self.indent),
        }
        out.push('\n');
        if matches!(directive, D::AttributeBegin | D::ObjectBegin(_)) {
            self.set_depth(self.depth + 1);
        }
    }

    /// The text for one directive (empty for pbrt-v3's WorldEnd).
    pub fn format(&mut self, directive: &Directive) -> String {
        let mut out = String::new();
        self.write(directive, &mut out);
        out
    }

    fn set_depth(&mut self, depth: usize) {
        self.depth = depth;
        self.indent = "    ".repeat(depth);
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
            "WorldBegin AttributeBegin Shape \"sphere\" \"float radius\" 1 AttributeEnd Include \"x.pbrt\" WorldEnd",
        )
        .follow_includes(false)
        .map(|d| f.format(&d.unwrap().directive))
        .collect();
        assert_eq!(
            text,
            "\nWorldBegin\n\nAttributeBegin\n    Shape \"sphere\"\n        \"float radius\" [ 1 ]\nAttributeEnd\nInclude \"x.pbrt\"\n"
        );
    }
}
