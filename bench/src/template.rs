//! The reports' prose, kept in Markdown template files
//! (`bench/templates/`) and filled by name.
//!
//! A template file is a list of named parts: each begins with a line
//! `@@ name`, and its text runs to the next such line (blank lines at its
//! end dropped; it ends with one newline). Text before the first part is a
//! note for the reader of the file and is not used. Placeholders are
//! `{{key}}`. Filling checks both ways, every placeholder given a value and
//! every value used, so that the prose and the code filling it cannot
//! drift apart unnoticed (each template's tests fill every part).

use crate::error::Error;
use std::fmt::Display;

/// A template file, compiled into the program.
#[derive(Clone, Copy, Debug)]
pub struct Template {
    /// The file's name, for errors.
    pub name: &'static str,
    pub text: &'static str,
}

/// The line that opens a part.
const PART_MARK: &str = "@@ ";

impl Template {
    /// The text of part `part`, ending in one newline.
    pub fn part(&self, part: &str) -> Result<String, Error> {
        let mut lines = self.text.lines();
        fn opening(line: &str) -> Option<&str> {
            line.strip_prefix(PART_MARK).map(str::trim)
        }
        if !lines.any(|line| opening(line) == Some(part)) {
            return Err(self.error(format!("no part {part:?}")));
        }
        let body: Vec<&str> = lines.take_while(|line| opening(line).is_none()).collect();
        let mut text = body.join("\n").trim_end_matches('\n').to_string();
        text.push('\n');
        Ok(text)
    }

    /// Part `part` with each `{{key}}` replaced by its value.
    pub fn fill(&self, part: &str, values: &[(&str, &dyn Display)]) -> Result<String, Error> {
        let text = self.part(part)?;
        let mut used = vec![false; values.len()];
        let mut out = String::with_capacity(text.len());
        let mut rest = text.as_str();
        while let Some(start) = rest.find("{{") {
            out.push_str(&rest[..start]);
            let after = &rest[start + 2..];
            let Some(end) = after.find("}}") else {
                return Err(self.error(format!("part {part:?}: a {{{{ without }}}}")));
            };
            let key = &after[..end];
            let Some(i) = values.iter().position(|(k, _)| *k == key) else {
                return Err(self.error(format!("part {part:?}: no value for {{{{{key}}}}}")));
            };
            used[i] = true;
            out.push_str(&values[i].1.to_string());
            rest = &after[end + 2..];
        }
        out.push_str(rest);
        if let Some(i) = used.iter().position(|u| !u) {
            return Err(self.error(format!("part {part:?} has no {{{{{}}}}}", values[i].0)));
        }
        Ok(out)
    }

    /// A part filled and trimmed, for a phrase set inside a sentence.
    pub fn phrase(&self, part: &str, values: &[(&str, &dyn Display)]) -> Result<String, Error> {
        Ok(self.fill(part, values)?.trim().to_string())
    }

    fn error(&self, message: String) -> Error {
        Error::Template {
            template: self.name.to_string(),
            message,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: Template = Template {
        name: "test.md",
        text:
            "A note.\n@@ first\nHello {{who}}, {{n}} times.\n\n\n@@ second\n{{a}}{{b}}\n@@ empty\n",
    };

    #[test]
    fn parts_are_found_and_filled() {
        assert_eq!(T.part("first").unwrap(), "Hello {{who}}, {{n}} times.\n");
        assert_eq!(
            T.fill("first", &[("n", &3), ("who", &"you")]).unwrap(),
            "Hello you, 3 times.\n"
        );
        assert_eq!(T.fill("second", &[("a", &1), ("b", &"x")]).unwrap(), "1x\n");
        assert_eq!(T.part("empty").unwrap(), "\n");
        assert_eq!(
            T.phrase("second", &[("a", &" a"), ("b", &"b ")]).unwrap(),
            "ab"
        );
    }

    #[test]
    fn mismatches_are_errors() {
        // A missing part, a placeholder without a value, a value without a
        // placeholder, an unclosed placeholder.
        assert!(T.part("third").is_err());
        assert!(T.fill("first", &[("who", &"you")]).is_err());
        assert!(T
            .fill("first", &[("who", &"you"), ("n", &1), ("x", &2)])
            .is_err());
        let open = Template {
            name: "open.md",
            text: "@@ p\n{{a\n",
        };
        assert!(open.fill("p", &[("a", &1)]).is_err());
        // A value is not searched for placeholders again.
        assert_eq!(
            T.fill("second", &[("a", &"{{b}}"), ("b", &2)]).unwrap(),
            "{{b}}2\n"
        );
    }
}
