//! pbrt-v3 names mapped to pbrt-v4 meaning, as pbrt-v4's `--upgrade` does.
//!
//! pbrt-v4 itself refuses pbrt-v3 files until they are upgraded; here they
//! are read directly. Each rule fires only on a name that pbrt-v4 does not
//! use, so pbrt-v4 files pass through untouched. Every rewrite is reported
//! (the parser shows each distinct note once).

use crate::directive::{Directive, Entity};
use crate::list::List;
use crate::name::Name;
use crate::param::{Param, ParamType, Values};

impl Entity {
    fn has(&self, name: &str) -> bool {
        self.params.iter().any(|p| p.name == name)
    }

    /// Removes and returns every parameter called `name`.
    fn take(&mut self, name: &str) -> Vec<Param> {
        let (taken, kept) = std::mem::take(&mut self.params)
            .into_iter()
            .partition(|p| p.name == name);
        self.params = kept;
        taken
    }

    fn rename(&mut self, from: &str, to: &str) -> bool {
        let mut renamed = false;
        for p in self.params.iter_mut().filter(|p| p.name == from) {
            p.name = to.into();
            renamed = true;
        }
        renamed
    }

    /// A parameter like an existing one (for its location), with new content.
    fn push_like(&mut self, like: Option<&Param>, ty: ParamType, name: &str, values: Values) {
        let location = like
            .map(|p| p.location.clone())
            .or_else(|| self.params.first().map(|p| p.location.clone()))
            .unwrap_or_else(crate::Location::nowhere);
        self.params.push(Param {
            ty,
            v3_type: false,
            name: name.into(),
            values,
            location,
        });
    }
}

/// The single grey value of an `rgb` parameter, if it is one.
fn grey(p: &Param) -> Option<f64> {
    match (p.ty, p.numbers()) {
        (ParamType::Rgb, [r, g, b]) if r == g && g == b => Some(*r),
        _ => None,
    }
}

/// Rewrites pbrt-v3 names in `directive`; a note for each rewrite.
pub fn upgrade(directive: &mut Directive, notes: &mut Vec<String>) {
    let keyword = directive.keyword();
    match directive {
        Directive::Film(e) => film(e, notes),
        Directive::Sampler(e) => {
            let new = match e.kind.as_str() {
                "lowdiscrepancy" | "02sequence" => "paddedsobol",
                "maxmindist" => "pmj02bn",
                "random" => "independent",
                _ => "",
            };
            rename_kind(e, new, "Sampler", notes);
        }
        Directive::Integrator(e) => integrator(e, notes),
        Directive::PixelFilter(e) => filter(e, notes),
        Directive::Camera(e) => {
            if e.kind == "environment" {
                rename_kind(e, "spherical", "Camera", notes);
                let like = e.params.first().cloned();
                e.push_like(
                    like.as_ref(),
                    ParamType::String,
                    "mapping",
                    Values::Strings(List::one(Name::new("equirectangular"))),
                );
            }
            if e.kind == "realistic" && !e.take("simpleweighting").is_empty() {
                notes.push(
                    "pbrt-v3 \"simpleweighting\" of the realistic camera dropped (not in pbrt-v4)"
                        .into(),
                );
            }
        }
        Directive::Material(e) => material(e, notes),
        Directive::MakeNamedMaterial(e) => {
            // The material type is the "string type" parameter.
            let ty = e
                .param("type")
                .and_then(|p| p.strings().first())
                .map_or_else(String::new, |s| s.to_string());
            let mut inner = Entity {
                kind: ty.clone(),
                params: std::mem::take(&mut e.params),
            };
            material(&mut inner, notes);
            e.params = inner.params;
            if inner.kind != ty {
                if let Some(p) = e.params.iter_mut().find(|p| p.name == "type") {
                    p.values = Values::Strings(List::one(Name::from(inner.kind)));
                }
            }
        }
        Directive::Texture {
            value_type, class, ..
        } => {
            if value_type == "color" {
                notes.push("pbrt-v3 texture type \"color\" read as \"spectrum\"".into());
                *value_type = "spectrum".into();
            }
            texture(value_type, class, notes);
        }
        Directive::LightSource(e) => light(e, notes),
        Directive::AreaLightSource(e) => {
            if e.kind == "area" {
                rename_kind(e, "diffuse", "AreaLightSource", notes);
            }
            if !e.take("nsamples").is_empty() {
                notes.push("pbrt-v3 area light \"nsamples\" dropped (pbrt-v4 has no per-light sample counts)".into());
            }
            let scale = light_scale(e, notes);
            blackbody(e, "L", scale, notes);
        }
        Directive::Shape(e) => shape(e, notes),
        Directive::MakeNamedMedium(e) => {
            for p in e.params.iter_mut().filter(|p| p.name == "type") {
                if p.strings() == ["heterogeneous"] {
                    p.values = Values::Strings(List::one(Name::new("uniformgrid")));
                    notes.push("pbrt-v3 medium \"heterogeneous\" read as \"uniformgrid\"".into());
                }
            }
        }
        _ => {}
    }
    // pbrt-v3 parameter type names.
    let params: Option<&mut Vec<Param>> = match directive {
        Directive::Film(e)
        | Directive::Sampler(e)
        | Directive::Integrator(e)
        | Directive::PixelFilter(e)
        | Directive::Camera(e)
        | Directive::Material(e)
        | Directive::MakeNamedMaterial(e)
        | Directive::LightSource(e)
        | Directive::AreaLightSource(e)
        | Directive::Shape(e)
        | Directive::MakeNamedMedium(e)
        | Directive::Accelerator(e)
        | Directive::Attribute(e) => Some(&mut e.params),
        Directive::Texture { class, .. } => Some(&mut class.params),
        _ => None,
    };
    for p in params.into_iter().flatten() {
        if let Some(v3) = std::mem::take(&mut p.v3_type)
            .then(|| p.ty.v3_name())
            .flatten()
        {
            notes.push(format!(
                "pbrt-v3 parameter type \"{v3}\" read as \"{}\" ({keyword})",
                p.ty.name()
            ));
        }
    }
    if let Directive::WorldEnd = directive {
        notes.push(
            "pbrt-v3 WorldEnd ignored (pbrt-v4 ends the world block at the end of the file)".into(),
        );
    }
}

fn rename_kind(e: &mut Entity, new: &str, directive: &str, notes: &mut Vec<String>) {
    if !new.is_empty() && e.kind != new {
        notes.push(format!(
            "pbrt-v3 {directive} \"{}\" read as \"{new}\"",
            e.kind
        ));
        e.kind = new.to_string();
    }
}

fn rename_param(e: &mut Entity, from: &str, to: &str, what: &str, notes: &mut Vec<String>) {
    if e.rename(from, to) {
        notes.push(format!(
            "pbrt-v3 {what} parameter \"{from}\" read as \"{to}\""
        ));
    }
}

fn film(e: &mut Entity, notes: &mut Vec<String>) {
    if e.kind == "image" {
        rename_kind(e, "rgb", "Film", notes);
    }
    for p in e.take("maxsampleluminance") {
        notes.push("pbrt-v3 Film \"maxsampleluminance\" read as \"maxcomponentvalue\"".into());
        let v = p.numbers().first().copied().unwrap_or(f64::INFINITY);
        e.push_like(
            Some(&p),
            ParamType::Float,
            "maxcomponentvalue",
            Values::Numbers(List::from([v])),
        );
    }
    for p in e.take("scale") {
        notes.push("pbrt-v3 Film \"scale\" read as \"iso\" = 100 × scale".into());
        let v = p.numbers().first().copied().unwrap_or(1.0);
        e.push_like(
            Some(&p),
            ParamType::Float,
            "iso",
            Values::Numbers(List::from([100.0 * v])),
        );
    }
}

fn integrator(e: &mut Entity, notes: &mut Vec<String>) {
    if !e.take("rrthreshold").is_empty() {
        notes.push("pbrt-v3 Integrator \"rrthreshold\" dropped (not in pbrt-v4)".into());
    }
    for p in e.take("lightsamplestrategy") {
        notes.push("pbrt-v3 Integrator \"lightsamplestrategy\" read as \"lightsampler\"".into());
        let v = match p.strings().first().map(Name::as_str) {
            Some("spatial") | None => "bvh".to_string(),
            Some(other) => other.to_string(),
        };
        e.push_like(
            Some(&p),
            ParamType::String,
            "lightsampler",
            Values::Strings(List::one(Name::from(v))),
        );
    }
    if e.kind == "sppm" {
        e.take("imagewritefrequency");
        if !e.take("numiterations").is_empty() {
            notes.push("pbrt-v3 SPPM \"numiterations\" dropped: pbrt-v4 takes it from the sampler's pixel samples".into());
        }
    }
    if e.kind == "directlighting" {
        rename_kind(e, "path", "Integrator", notes);
        e.take("strategy");
        e.take("maxdepth");
        e.push_like(
            None,
            ParamType::Integer,
            "maxdepth",
            Values::Numbers(List::from([1.0])),
        );
    }
}

fn filter(e: &mut Entity, notes: &mut Vec<String>) {
    rename_param(e, "xwidth", "xradius", "PixelFilter", notes);
    rename_param(e, "ywidth", "yradius", "PixelFilter", notes);
    if e.kind == "gaussian" {
        for p in e.take("alpha") {
            notes.push(
                "pbrt-v3 gaussian filter \"alpha\" read as \"sigma\" = 1/sqrt(2 alpha)".into(),
            );
            let alpha = p.numbers().first().copied().unwrap_or(2.0);
            e.push_like(
                Some(&p),
                ParamType::Float,
                "sigma",
                Values::Numbers(List::from([1.0 / (2.0 * alpha).sqrt()])),
            );
        }
    }
}

/// Drops an `rgb` parameter that pbrt-v4 has no use for; notes it when its
/// value was not the one that makes it irrelevant.
fn drop_constant(
    e: &mut Entity,
    name: &str,
    irrelevant: f64,
    material: &str,
    notes: &mut Vec<String>,
) -> bool {
    let taken = e.take(name);
    let matched = taken.iter().any(|p| grey(p) == Some(irrelevant));
    if !taken.is_empty() && !matched {
        notes.push(format!(
            "pbrt-v3 parameter \"{name}\" has no equivalent in the pbrt-v4 \"{material}\" material and was dropped"
        ));
    }
    matched
}

fn material(e: &mut Entity, notes: &mut Vec<String>) {
    let v3 = e.kind.clone();
    if matches!(v3.as_str(), "glass" | "uber") {
        rename_param(e, "index", "eta", "material", notes);
    }
    rename_param(e, "bumpmap", "displacement", "material", notes);
    match v3.as_str() {
        "uber" | "plastic" => {
            let mut new = "coateddiffuse";
            if drop_constant(e, "Ks", 0.0, "diffuse", notes) {
                new = "diffuse";
                e.take("roughness");
                if v3 == "plastic" {
                    e.take("eta");
                }
            }
            if v3 == "uber" {
                drop_constant(e, "Kr", 0.0, new, notes);
                drop_constant(e, "Kt", 0.0, new, notes);
                for p in e.take("opacity") {
                    if grey(&p) != Some(1.0) {
                        notes.push(
                            "pbrt-v3 uber \"opacity\" is not supported in pbrt-v4 and was dropped"
                                .into(),
                        );
                    }
                }
            }
            e.take("remaproughness").into_iter().for_each(|p| {
                if new == "coateddiffuse" {
                    e.params.push(p)
                }
            });
            rename_param(e, "Kd", "reflectance", "material", notes);
            rename_kind(e, new, "Material", notes);
        }
        "substrate" => {
            drop_constant(e, "Ks", 1.0, "coateddiffuse", notes);
            rename_param(e, "Kd", "reflectance", "material", notes);
            rename_kind(e, "coateddiffuse", "Material", notes);
        }
        "glass" => {
            drop_constant(e, "Kr", 1.0, "dielectric", notes);
            drop_constant(e, "Kt", 1.0, "dielectric", notes);
            rename_kind(e, "dielectric", "Material", notes);
        }
        "metal" => {
            drop_constant(e, "Kr", 1.0, "conductor", notes);
            rename_kind(e, "conductor", "Material", notes);
        }
        "mirror" => {
            let kr = e.take("Kr");
            let reflectance = kr
                .first()
                .map_or(Values::Numbers(List::from([0.9, 0.9, 0.9])), |p| {
                    p.values.clone()
                });
            let ty = kr.first().map_or(ParamType::Rgb, |p| p.ty);
            e.push_like(kr.first(), ty, "reflectance", reflectance);
            e.push_like(
                None,
                ParamType::Float,
                "roughness",
                Values::Numbers(List::from([0.0])),
            );
            rename_kind(e, "conductor", "Material", notes);
        }
        "matte" => {
            e.take("sigma");
            rename_param(e, "Kd", "reflectance", "material", notes);
            rename_kind(e, "diffuse", "Material", notes);
        }
        "translucent" => {
            rename_param(e, "Kd", "transmittance", "material", notes);
            drop_constant(e, "reflect", 0.0, "diffusetransmission", notes);
            drop_constant(e, "transmit", 1.0, "diffusetransmission", notes);
            drop_constant(e, "Ks", 0.0, "diffusetransmission", notes);
            e.take("roughness");
            rename_kind(e, "diffusetransmission", "Material", notes);
        }
        "kdsubsurface" => {
            rename_param(e, "Kd", "reflectance", "material", notes);
            rename_kind(e, "subsurface", "Material", notes);
        }
        "disney" => {
            rename_param(e, "color", "reflectance", "material", notes);
            rename_kind(e, "diffuse", "Material", notes);
        }
        "hair" => rename_param(e, "color", "reflectance", "hair material", notes),
        "" | "none" => rename_kind(e, "interface", "Material", notes),
        "mix" => {
            let one = e.take("namedmaterial1");
            let two = e.take("namedmaterial2");
            if let (Some(a), Some(b)) = (one.first(), two.first()) {
                notes.push("pbrt-v3 mix \"namedmaterial1/2\" read as \"materials\"".into());
                let names = vec![
                    b.strings().first().cloned().unwrap_or_default(),
                    a.strings().first().cloned().unwrap_or_default(),
                ];
                e.push_like(
                    Some(a),
                    ParamType::String,
                    "materials",
                    Values::Strings(names.into()),
                );
            }
            let amount = e.take("amount");
            for p in amount {
                match (p.ty, p.numbers()) {
                    (ParamType::Rgb, [r, g, b]) => {
                        notes.push("pbrt-v3 rgb mix \"amount\" read as its average".into());
                        e.push_like(
                            Some(&p),
                            ParamType::Float,
                            "amount",
                            Values::Numbers(List::from([(r + g + b) / 3.0])),
                        );
                    }
                    _ => e.params.push(p),
                }
            }
        }
        _ => {}
    }
}

fn texture(value_type: &str, class: &mut Entity, notes: &mut Vec<String>) {
    match class.kind.as_str() {
        "scale" if class.has("tex1") || class.has("tex2") => {
            if value_type == "float" {
                rename_param(class, "tex1", "tex", "scale texture", notes);
                rename_param(class, "tex2", "scale", "scale texture", notes);
            } else {
                // One of the two must be a grey rgb: it becomes the scale.
                let grey_name = ["tex1", "tex2"]
                    .into_iter()
                    .find(|n| class.param(n).and_then(grey).is_some());
                if let Some(n) = grey_name {
                    let p = class.take(n).remove(0);
                    let other = if n == "tex1" { "tex2" } else { "tex1" };
                    rename_param(class, other, "tex", "scale texture", notes);
                    class.push_like(
                        Some(&p),
                        ParamType::Float,
                        "scale",
                        Values::Numbers(List::from([grey(&p).unwrap_or(1.0)])),
                    );
                } else {
                    rename_param(class, "tex1", "tex", "scale texture", notes);
                    rename_param(class, "tex2", "scale", "scale texture", notes);
                }
            }
        }
        "imagemap" | "ptex" => {
            for p in class.take("trilinear") {
                let filter = if p.bools().first() == Some(&true) {
                    "trilinear"
                } else {
                    "bilinear"
                };
                notes.push("pbrt-v3 imagemap \"trilinear\" read as \"filter\"".into());
                class.push_like(
                    Some(&p),
                    ParamType::String,
                    "filter",
                    Values::Strings(List::one(Name::new(filter))),
                );
            }
            for p in class.take("gamma") {
                let encoding = match (p.ty, p.numbers(), p.bools()) {
                    (ParamType::Float, [g], _) if *g != 0.0 => format!("gamma {g}"),
                    (ParamType::Bool, _, [true]) => "sRGB".into(),
                    _ => "linear".into(),
                };
                notes.push("pbrt-v3 imagemap \"gamma\" read as \"encoding\"".into());
                class.push_like(
                    Some(&p),
                    ParamType::String,
                    "encoding",
                    Values::Strings(List::one(Name::from(encoding))),
                );
            }
        }
        _ => {}
    }
}

/// Folds a pbrt-v3 grey `rgb scale` into a float scale; returns the factor.
fn light_scale(e: &mut Entity, notes: &mut Vec<String>) -> f64 {
    let mut factor = 1.0;
    let scales = e.take("scale");
    for p in scales {
        match p.ty {
            ParamType::Rgb => {
                notes.push(
                    "pbrt-v3 rgb light \"scale\" read as a float (pbrt-v4 scales are floats)"
                        .into(),
                );
                let [r, g, b] = [0, 1, 2].map(|i| p.numbers().get(i).copied().unwrap_or(1.0));
                factor *= (r + g + b) / 3.0;
            }
            _ => e.params.push(p),
        }
    }
    factor
}

/// A pbrt-v3 two-value blackbody (temperature, scale) becomes one value and
/// a scale.
fn blackbody(e: &mut Entity, name: &str, mut scale: f64, notes: &mut Vec<String>) {
    for p in e
        .params
        .iter_mut()
        .filter(|p| p.name == name && p.ty == ParamType::Blackbody)
    {
        if let Values::Numbers(v) = &mut p.values {
            if v.len() == 2 {
                notes.push("pbrt-v3 two-value blackbody (temperature, scale) read as temperature and \"scale\"".into());
                scale *= v[1];
                *v = List::one(v[0]);
            }
        }
    }
    if scale != 1.0 {
        let existing = e.take("scale");
        let base = existing
            .first()
            .and_then(|p| p.numbers().first().copied())
            .unwrap_or(1.0);
        e.push_like(
            existing.first(),
            ParamType::Float,
            "scale",
            Values::Numbers(List::from([base * scale])),
        );
    }
}

fn light(e: &mut Entity, notes: &mut Vec<String>) {
    let mut scale = light_scale(e, notes);
    if !e.take("samples").is_empty() || !e.take("nsamples").is_empty() {
        notes.push(
            "pbrt-v3 light \"nsamples\" dropped (pbrt-v4 has no per-light sample counts)".into(),
        );
    }
    if e.has("mapname") {
        let radiance = if e.kind == "projection" { "I" } else { "L" };
        for p in e.take(radiance) {
            match grey(&p) {
                Some(g) => scale *= g,
                None => {
                    notes.push(format!("pbrt-v3 coloured \"{radiance}\" with \"mapname\" dropped: pbrt-v4 uses the image's colours"));
                }
            }
        }
        rename_param(e, "mapname", "filename", "light", notes);
    }
    blackbody(e, "I", 1.0, notes);
    blackbody(e, "L", scale, notes);
}

fn shape(e: &mut Entity, notes: &mut Vec<String>) {
    if e.kind == "loopsubdiv" {
        rename_param(e, "nlevels", "levels", "loopsubdiv", notes);
    }
    if matches!(e.kind.as_str(), "trianglemesh" | "plymesh") {
        if !e.take("discarddegenerateUVs").is_empty() {
            notes.push("pbrt-v3 \"discarddegenerateUVs\" dropped (not in pbrt-v4)".into());
        }
        e.params
            .retain(|p| !(p.name == "shadowalpha" && p.ty == ParamType::Texture));
    }
    if e.kind == "trianglemesh"
        && !e
            .params
            .iter()
            .any(|p| p.name == "uv" && p.ty == ParamType::Point2)
    {
        let st: Vec<Param> = e.take("st");
        let uv: Vec<Param> = e.take("uv");
        if let Some(p) = st.iter().chain(uv.iter()).next() {
            notes.push("pbrt-v3 \"float uv\"/\"st\" read as \"point2 uv\"".into());
            let values = p.numbers().to_vec();
            e.push_like(
                Some(p),
                ParamType::Point2,
                "uv",
                Values::Numbers(values.into()),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{Directive, Parser};

    fn upgraded(text: &str) -> (Vec<Directive>, Vec<String>) {
        let mut parser = Parser::from_text("<v3>", text);
        let ds = parser.by_ref().map(|d| d.unwrap().directive).collect();
        let notes = parser
            .take_warnings()
            .into_iter()
            .map(|w| w.message)
            .collect();
        (ds, notes)
    }

    #[test]
    fn v3_materials_and_types() {
        let (ds, notes) = upgraded(
            "Material \"matte\" \"color Kd\" [.5 .5 .5]\nMaterial \"plastic\" \"rgb Kd\" [1 0 0] \"rgb Ks\" [0 0 0]\n\
             Material \"matte\" \"color Kd\" [.2 .2 .2]",
        );
        assert_eq!(
            ds[0].to_string(),
            "Material \"diffuse\"\n    \"rgb reflectance\" [ 0.5 0.5 0.5 ]"
        );
        assert_eq!(
            ds[1].to_string(),
            "Material \"diffuse\"\n    \"rgb reflectance\" [ 1 0 0 ]"
        );
        // Each mapping is noted once.
        assert_eq!(notes.iter().filter(|n| n.contains("\"color\"")).count(), 1);
    }

    #[test]
    fn v3_film_sampler_filter_light() {
        let (ds, _) = upgraded(
            "Film \"image\" \"float maxsampleluminance\" 10\nSampler \"lowdiscrepancy\"\n\
             PixelFilter \"gaussian\" \"float xwidth\" 2\nWorldBegin\n\
             LightSource \"infinite\" \"string mapname\" \"sky.exr\" \"color L\" [2 2 2]\n\
             AreaLightSource \"area\" \"blackbody L\" [6500 3]\nWorldEnd",
        );
        assert_eq!(
            ds[0].to_string(),
            "Film \"rgb\"\n    \"float maxcomponentvalue\" [ 10 ]"
        );
        assert_eq!(ds[1].to_string(), "Sampler \"paddedsobol\"");
        assert_eq!(
            ds[2].to_string(),
            "PixelFilter \"gaussian\"\n    \"float xradius\" [ 2 ]"
        );
        assert_eq!(
            ds[4].to_string(),
            "LightSource \"infinite\"\n    \"string filename\" [ \"sky.exr\" ]\n    \"float scale\" [ 2 ]"
        );
        assert_eq!(
            ds[5].to_string(),
            "AreaLightSource \"diffuse\"\n    \"blackbody L\" [ 6500 ]\n    \"float scale\" [ 3 ]"
        );
        assert_eq!(ds[6], Directive::WorldEnd);
    }

    #[test]
    fn v4_files_pass_untouched() {
        let text = "Material \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ] \"float roughness\" [ 0 ]";
        let (ds, notes) = upgraded(text);
        assert_eq!(ds[0].to_string().replace("\n   ", ""), text);
        assert!(notes.is_empty());
    }
}
