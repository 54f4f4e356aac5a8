//! Typed parameter lookups with defaults, and the report of parameters no
//! lookup asked for.
//!
//! A [`ParamSet`] holds a directive's parameters, then those of the
//! `Attribute` directives in force (which a directive's own parameters
//! override, and which may go unused). Lookups match name *and* type; a
//! parameter whose name matches but whose type is not one the lookup
//! accepts is an error, as is a parameter nothing asked for.

use crate::error::{scene_error, Result, SceneError};
use glam::{DVec2, DVec3};
use pbrt_parser::{Location, Param, ParamType, Values};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Parameters of one entity, with per-parameter "was looked up" flags
/// (atomic, so that the shapes of a description can be made in parallel).
#[derive(Debug, Default)]
pub struct ParamSet {
    /// Boxed, not a vector: a description holds millions of these.
    params: Box<[Param]>,
    /// How many of `params` are the directive's own; the rest came from
    /// `Attribute` (never reported unused).
    own: usize,
    /// "Looked up" flags of the first 64 parameters, as bits (a description
    /// holds millions of these: no allocation for them).
    used: AtomicU64,
    /// Flags of parameters past the 64th.
    used_beyond: Box<[AtomicBool]>,
}

impl Clone for ParamSet {
    fn clone(&self) -> Self {
        ParamSet {
            params: self.params.clone(),
            own: self.own,
            used: AtomicU64::new(self.used.load(Ordering::Relaxed)),
            used_beyond: self
                .used_beyond
                .iter()
                .map(|u| AtomicBool::new(u.load(Ordering::Relaxed)))
                .collect(),
        }
    }
}

impl PartialEq for ParamSet {
    fn eq(&self, other: &Self) -> bool {
        self.params == other.params
    }
}

/// Whether two parameter names are equal, their lengths and first bytes
/// compared before a call to compare their bytes: names that differ (most
/// of those a lookup meets: "width" and "basis", "P" and "N") mostly
/// differ there already.
#[inline]
fn same_name(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.as_bytes().first() == b.as_bytes().first() && a == b
}

impl ParamSet {
    pub fn new(params: Vec<Param>, attributes: &[Param]) -> Self {
        let own = params.len();
        let mut all = params;
        // Later attributes override earlier ones: search them last-first.
        all.extend(attributes.iter().rev().cloned());
        ParamSet {
            used: AtomicU64::new(0),
            used_beyond: (64..all.len()).map(|_| AtomicBool::new(false)).collect(),
            params: all.into_boxed_slice(),
            own,
        }
    }

    fn is_attribute(&self, i: usize) -> bool {
        i >= self.own
    }

    fn mark_used(&self, i: usize) {
        if i < 64 {
            self.used.fetch_or(1 << i, Ordering::Relaxed);
        } else {
            self.used_beyond[i - 64].store(true, Ordering::Relaxed);
        }
    }

    fn is_used(&self, i: usize) -> bool {
        if i < 64 {
            self.used.load(Ordering::Relaxed) & (1 << i) != 0
        } else {
            self.used_beyond[i - 64].load(Ordering::Relaxed)
        }
    }

    pub fn iter(&self) -> impl ExactSizeIterator<Item = &Param> {
        self.params.iter()
    }

    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    /// How many of the parameters are the directive's own (the rest,
    /// from `Attribute`, follow them in [`ParamSet::iter`]).
    pub fn own_count(&self) -> usize {
        self.own
    }

    /// The directive's own parameters (not the attributes), for printing.
    pub fn own(&self) -> impl Iterator<Item = &Param> {
        self.params[..self.own].iter()
    }

    /// The parameter called `name` (marked used), if any: the directive's
    /// last of that name, else the first attribute's; an error when its
    /// type is not among `types`.
    pub fn find(&self, name: &str, types: &[ParamType]) -> Result<Option<&Param>> {
        // One pass (a hair file looks up about nine names per curve): the
        // directive's own parameters come before the attributes, so the
        // last match among them, else the first after them, is the one.
        let mut found = None;
        let mut same_named = 0;
        for (i, p) in self.params.iter().enumerate() {
            if !same_name(&p.name, name) {
                continue;
            }
            same_named += 1;
            if !self.is_attribute(i) || found.is_none() {
                found = Some(i);
            }
        }
        let Some(i) = found else {
            return Ok(None);
        };
        let p = &self.params[i];
        // Same-named parameters are all accounted for by this lookup.
        if same_named > 1 {
            for (j, q) in self.params.iter().enumerate() {
                if same_name(&q.name, name) && types.contains(&q.ty) {
                    self.mark_used(j);
                }
            }
        }
        if !types.contains(&p.ty) {
            let expected: Vec<&str> = types.iter().map(|t| t.name()).collect();
            return scene_error(
                format!(
                    "\"{} {}\": parameter \"{}\" has the wrong type; expected {}",
                    p.ty.name(),
                    p.name,
                    p.name,
                    expected.join(" or ")
                ),
                &p.location,
            );
        }
        self.mark_used(i);
        Ok(Some(p))
    }

    /// Whether a parameter (the directive's or an attribute's) is called
    /// each of `names`, found in one pass and marked used by none: a
    /// lookup of an absent name ([`ParamSet::find`]) scans every
    /// parameter, and each of a hair file's curves has lookups of nine
    /// names, most of them absent.
    pub fn has_each<const N: usize>(&self, names: [&str; N]) -> [bool; N] {
        let mut present = [false; N];
        for p in self.params.iter() {
            for (k, name) in names.iter().enumerate() {
                if same_name(&p.name, name) {
                    present[k] = true;
                }
            }
        }
        present
    }

    fn one_number(&self, name: &str, ty: ParamType) -> Result<Option<(f64, &Location)>> {
        let Some(p) = self.find(name, &[ty])? else {
            return Ok(None);
        };
        match p.numbers() {
            [x] => Ok(Some((*x, &p.location))),
            [] => scene_error(format!("no values provided for \"{name}\""), &p.location),
            _ => scene_error(
                format!("more than one value provided for \"{name}\""),
                &p.location,
            ),
        }
    }

    pub fn float(&self, name: &str, default: f64) -> Result<f64> {
        Ok(self
            .one_number(name, ParamType::Float)?
            .map_or(default, |(x, _)| x))
    }

    pub fn int(&self, name: &str, default: i32) -> Result<i32> {
        Ok(self
            .one_number(name, ParamType::Integer)?
            .map_or(default, |(x, _)| x as i32))
    }

    pub fn bool(&self, name: &str, default: bool) -> Result<bool> {
        let Some(p) = self.find(name, &[ParamType::Bool])? else {
            return Ok(default);
        };
        match p.bools() {
            [b] => Ok(*b),
            _ => scene_error(format!("expected one value for \"{name}\""), &p.location),
        }
    }

    pub fn string(&self, name: &str, default: &str) -> Result<String> {
        self.string_ref(name, default).map(str::to_string)
    }

    /// [`ParamSet::string`] without the copy (a hair file looks strings
    /// up once per curve).
    pub fn string_ref<'a>(&'a self, name: &str, default: &'a str) -> Result<&'a str> {
        let Some(p) = self.find(name, &[ParamType::String])? else {
            return Ok(default);
        };
        match p.strings() {
            [s] => Ok(s.as_str()),
            _ => scene_error(format!("expected one value for \"{name}\""), &p.location),
        }
    }

    /// A one-valued string parameter and where it is written, for errors
    /// about what it names (a file); `None` when absent.
    pub fn string_at(&self, name: &str) -> Result<Option<(String, Location)>> {
        let Some(p) = self.find(name, &[ParamType::String])? else {
            return Ok(None);
        };
        match p.strings() {
            [s] => Ok(Some((s.to_string(), p.location.clone()))),
            _ => scene_error(format!("expected one value for \"{name}\""), &p.location),
        }
    }

    /// The name of the texture bound to `name`, if any.
    pub fn texture(&self, name: &str) -> Result<Option<String>> {
        let Some(p) = self.find(name, &[ParamType::Texture])? else {
            return Ok(None);
        };
        match p.strings() {
            [s] => Ok(Some(s.to_string())),
            _ => scene_error(
                format!("expected one texture name for \"{name}\""),
                &p.location,
            ),
        }
    }

    pub fn floats(&self, name: &str) -> Result<Vec<f64>> {
        Ok(self
            .find(name, &[ParamType::Float])?
            .map_or_else(Vec::new, |p| p.numbers().to_vec()))
    }

    pub fn ints(&self, name: &str) -> Result<Vec<i32>> {
        Ok(self
            .find(name, &[ParamType::Integer])?
            .map_or_else(Vec::new, |p| {
                p.numbers().iter().map(|&x| x as i32).collect()
            }))
    }

    pub fn strings(&self, name: &str) -> Result<Vec<String>> {
        Ok(self
            .find(name, &[ParamType::String])?
            .map_or_else(Vec::new, |p| {
                p.strings().iter().map(|s| s.to_string()).collect()
            }))
    }

    fn triples(&self, name: &str, ty: ParamType) -> Result<Vec<DVec3>> {
        Ok(self.find(name, &[ty])?.map_or_else(Vec::new, |p| {
            p.numbers()
                .chunks_exact(3)
                .map(|c| DVec3::new(c[0], c[1], c[2]))
                .collect()
        }))
    }

    pub fn point3s(&self, name: &str) -> Result<Vec<DVec3>> {
        self.triples(name, ParamType::Point3)
    }

    /// [`ParamSet::point3s`] as its coordinates, x y z of each point in
    /// turn, without the copy (a hair file's curves each have their own).
    pub fn point3_coordinates(&self, name: &str) -> Result<&[f64]> {
        Ok(self.find(name, &[ParamType::Point3])?.map_or(&[][..], |p| {
            let numbers = p.numbers();
            // Whole points only, as `point3s`.
            &numbers[..numbers.len() / 3 * 3]
        }))
    }

    pub fn vector3s(&self, name: &str) -> Result<Vec<DVec3>> {
        self.triples(name, ParamType::Vector3)
    }

    pub fn normals(&self, name: &str) -> Result<Vec<DVec3>> {
        self.triples(name, ParamType::Normal3)
    }

    pub fn point2s(&self, name: &str) -> Result<Vec<DVec2>> {
        Ok(self
            .find(name, &[ParamType::Point2])?
            .map_or_else(Vec::new, |p| {
                p.numbers()
                    .chunks_exact(2)
                    .map(|c| DVec2::new(c[0], c[1]))
                    .collect()
            }))
    }

    pub fn point3(&self, name: &str, default: DVec3) -> Result<DVec3> {
        let Some(p) = self.find(name, &[ParamType::Point3])? else {
            return Ok(default);
        };
        match p.numbers() {
            [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
            _ => scene_error(format!("expected one point for \"{name}\""), &p.location),
        }
    }

    /// Clears every "looked up" flag: the schema's check of names and
    /// types looks each parameter up, and the create function's lookups
    /// are the ones [`ParamSet::report_unused`] must judge.
    pub fn forget_used(&self) {
        self.used.store(0, Ordering::Relaxed);
        for flag in &self.used_beyond {
            flag.store(false, Ordering::Relaxed);
        }
    }

    /// The first parameter nothing looked up, as an error (pbrt-v4 treats
    /// unused parameters as errors: they are usually misspellings).
    /// `what` names the entity (made only for the error).
    pub fn report_unused(&self, what: impl FnOnce() -> String) -> Result<()> {
        for (i, p) in self.params.iter().enumerate() {
            if self.is_attribute(i) || self.is_used(i) {
                continue;
            }
            return Err(SceneError::new(
                format!(
                    "\"{} {}\": unused parameter (not a parameter of {})",
                    p.ty.name(),
                    p.name,
                    what()
                ),
                &p.location,
            )
            .into());
        }
        Ok(())
    }

    /// Values of a parameter for printing a summary (first match).
    pub fn values(&self, name: &str) -> Option<&Values> {
        self.params
            .iter()
            .find(|p| p.name == name)
            .map(|p| &p.values)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pbrt_parser::{Directive, Parser};

    fn params(text: &str) -> ParamSet {
        let d = Parser::from_text("<t>", text).next().unwrap().unwrap();
        let Directive::Shape(e) = d.directive else {
            panic!()
        };
        ParamSet::new(e.params, &[])
    }

    #[test]
    fn typed_lookups_with_defaults() {
        let p = params(
            "Shape \"sphere\" \"float radius\" 2 \"integer n\" [3] \"point3 P\" [1 2 3 4 5 6]",
        );
        assert_eq!(p.float("radius", 1.0).unwrap(), 2.0);
        assert_eq!(p.float("zmin", -1.0).unwrap(), -1.0);
        assert_eq!(p.int("n", 0).unwrap(), 3);
        assert_eq!(p.point3s("P").unwrap().len(), 2);
        p.report_unused(|| "sphere".into()).unwrap();
    }

    /// A directive's own parameter overrides an attribute's; of
    /// several of one name, the directive's last and the attributes'
    /// first (the latest `Attribute`) win; every one of the name and type
    /// asked for counts as used.
    #[test]
    fn the_last_own_then_the_latest_attribute_wins() {
        let parameters = |text: &str| {
            let d = Parser::from_text("<a>", text).next().unwrap().unwrap();
            let (Directive::Attribute(e) | Directive::Shape(e)) = d.directive else {
                panic!()
            };
            e.params
        };
        // In the order the builder passes them: the latest `Attribute` last.
        let mut older = parameters("Attribute \"shape\" \"float w\" 5 \"float v\" 7");
        older.extend(parameters(
            "Attribute \"shape\" \"float w\" 6 \"float v\" 8",
        ));
        let own = parameters("Shape \"curve\" \"float w\" 1 \"float w\" 2 \"float u\" 3");
        let set = ParamSet::new(own.clone(), &older);
        assert_eq!(set.float("w", 0.0).unwrap(), 2.0);
        assert_eq!(set.float("v", 0.0).unwrap(), 8.0);
        assert_eq!(set.float("x", 9.0).unwrap(), 9.0);
        let e = set
            .report_unused(|| "curve".into())
            .unwrap_err()
            .to_string();
        assert!(e.contains("\"float u\": unused"), "{e}");
        set.float("u", 0.0).unwrap();
        set.report_unused(|| "curve".into()).unwrap();
        // The losing `w`s and `v`s too (of the asked-for type).
        assert!((0..7).all(|i| set.is_used(i)));
    }

    /// A same-named parameter of another type is an error at the one
    /// that wins, and is not counted as used when it loses.
    #[test]
    fn a_wrong_type_is_reported_where_it_is_written() {
        let p = params("Shape \"curve\" \"float type\" 1\n \"string type\" \"flat\"");
        assert_eq!(p.string_ref("type", "cylinder").unwrap(), "flat");
        let e = p.report_unused(|| "curve".into()).unwrap_err().to_string();
        assert!(
            e.contains("\"float type\": unused") && e.contains("<t>:1:15"),
            "{e}"
        );
        let p = params("Shape \"curve\" \"string type\" \"flat\"\n \"float type\" 1");
        let e = p.string_ref("type", "cylinder").unwrap_err().to_string();
        assert!(e.contains("wrong type") && e.contains("<t>:2:2"), "{e}");
        let p = params("Shape \"curve\" \"string type\" [\"flat\" \"ribbon\"]");
        let e = p.string_ref("type", "cylinder").unwrap_err().to_string();
        assert!(e.contains("expected one value for \"type\""), "{e}");
        assert_eq!(
            params("Shape \"curve\"")
                .string_ref("type", "cylinder")
                .unwrap(),
            "cylinder"
        );
    }

    #[test]
    fn has_each_sees_own_and_attribute_parameters_and_marks_none() {
        let attributes = vec![params("Shape \"curve\" \"float width1\" 2")
            .iter()
            .next()
            .unwrap()
            .clone()];
        let own = params("Shape \"curve\" \"float width0\" 1 \"string type\" \"flat\"");
        let set = ParamSet::new(own.iter().cloned().collect(), &attributes);
        assert_eq!(
            set.has_each(["width", "width0", "width1", "type", "N"]),
            [false, true, true, true, false]
        );
        let e = set
            .report_unused(|| "curve".into())
            .unwrap_err()
            .to_string();
        assert!(e.contains("\"float width0\": unused"), "{e}");
    }

    #[test]
    fn names_are_the_same_only_when_spelt_alike() {
        assert!(same_name("width", "width"));
        assert!(same_name("", ""));
        assert!(!same_name("width", "basis"));
        assert!(!same_name("width0", "width1"));
        assert!(!same_name("width", "width0"));
        assert!(!same_name("P", "N"));
        assert!(!same_name("", "P"));
    }

    #[test]
    fn point_coordinates_are_whole_points_in_order() {
        let p = params("Shape \"curve\" \"point3 P\" [1 2 3 4 5 6]");
        assert_eq!(
            p.point3_coordinates("P").unwrap(),
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
        );
        assert!(p.point3_coordinates("Q").unwrap().is_empty());
        p.report_unused(|| "curve".into()).unwrap();
    }

    #[test]
    fn wrong_type_is_an_error_not_a_default() {
        let p = params("Shape \"sphere\" \"integer radius\" 2");
        let e = p.float("radius", 1.0).unwrap_err().to_string();
        assert!(e.contains("wrong type") && e.contains("<t>:1:16"), "{e}");
    }

    /// The schema's check looks every parameter up; what counts is what
    /// the create function reads afterwards: a parameter the schema lists
    /// but the create function does not read is reported.
    #[test]
    fn a_listed_parameter_the_creator_does_not_read_is_reported() {
        let p = params("Shape \"sphere\" \"float radius\" 2\n  \"float zmax\" 0.5");
        let here = p.iter().next().unwrap().location.clone();
        crate::scene_description::schema::check(
            crate::scene_description::schema::Category::Shape,
            "sphere",
            &p,
            &here,
        )
        .unwrap();
        p.float("radius", 1.0).unwrap();
        let e = p
            .report_unused(|| "shape \"sphere\"".into())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("\"float zmax\": unused parameter") && e.contains("<t>:2:3"),
            "{e}"
        );
        p.float("zmax", 1.0).unwrap();
        p.report_unused(|| "shape \"sphere\"".into()).unwrap();
    }

    #[test]
    fn unused_parameters_are_reported_with_location() {
        let p = params("Shape \"sphere\"\n  \"float radious\" 2");
        p.float("radius", 1.0).unwrap();
        let e = p.report_unused(|| "sphere".into()).unwrap_err().to_string();
        assert!(e.contains("radious") && e.contains("<t>:2:3"), "{e}");
    }
}
