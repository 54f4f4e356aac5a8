use crate::directive::Directive;
pub fn upgrade(_d: &mut Directive, _notes: &mut Vec<String>) {}
