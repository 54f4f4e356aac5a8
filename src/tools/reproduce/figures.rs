//! The paper's figures as `rpbrt reproduce` makes them: for each, the
//! scene files of its panels (in `pbrt-scenes/paper/`, built into the
//! binary so the command works from anywhere), the model each panel uses
//! (for Table 2), what the paper's caption claims, and the region its
//! brightness is measured in. Figs. 7 and 10 are plots from `rpbrt bcsdf`.

/// Which hair model a panel renders, for Table 2's columns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// pbrt-v4's hair (Chiang et al. 2016: circular fibres, rays only).
    Reference,
    /// Benamira & Pattanaik's dual model (elliptical fibres, diffraction).
    Dual,
}

/// One rendered panel.
pub struct Panel {
    /// The scene file in `pbrt-scenes/paper/` (its stem names the image).
    pub scene: &'static str,
    /// The panel's caption: the model and its parameters.
    pub label: &'static str,
    pub model: Model,
}

/// What a figure is made of.
pub enum Work {
    /// Rendered panels shown side by side with one exposure.
    Render {
        panels: &'static [Panel],
        /// Linear scale before the sRGB curve, the same for every panel.
        exposure: f32,
        /// Add a panel of the relative difference between these two
        /// panels (indices), full red at `difference_scale`.
        difference: Option<(usize, usize)>,
        difference_scale: f32,
        /// Samples per pixel in a preview (noise would hide a small
        /// difference).
        preview_spp: u32,
    },
    /// `rpbrt bcsdf` with these arguments (after which `--png FILE`),
    /// `caption` under it.
    Plot {
        bcsdf_args: &'static [&'static str],
        caption: &'static str,
    },
}

pub struct Figure {
    /// Short name: the output folder and `--only`'s value (`fig12`).
    pub id: &'static str,
    pub title: &'static str,
    /// What the paper's caption and text say the figure shows.
    pub claim: &'static str,
    pub work: Work,
    /// Named regions (x0, y0, x1, y1 as fractions of the image, y down)
    /// whose mean luminance is reported for each panel (and the first's
    /// mean saturation): where the paper's claim can be measured.
    pub regions: &'static [Region],
}

/// A named part of a figure's images.
pub struct Region {
    pub name: &'static str,
    pub bounds: [f32; 4],
}

const HAIR: Region = Region {
    name: "hair",
    bounds: [0.2, 0.1, 0.8, 0.95],
};
const HEAD_REGIONS: &[Region] = &[
    HAIR,
    Region {
        name: "top of the hair",
        bounds: [0.3, 0.1, 0.7, 0.3],
    },
];

pub const FIGURES: &[Figure] = &[
    Figure {
        id: "fig01",
        title: "Fig. 1: hair between the viewer and a strong warm light",
        claim: "Strong forward scattering (diffraction) brightens the fibres in front of the light; the ray model falls short.",
        work: Work::Render {
            panels: &[
                Panel { scene: "fig01-reference.pbrt", label: "reference (pbrt-v4 hair), melanin 8", model: Model::Reference },
                Panel { scene: "fig01-dual.pbrt", label: "dual: a 30, b 20 µm, d_diff 1", model: Model::Dual },
            ],
            exposure: 1.0,
            difference: None,
            difference_scale: 1.0,
            preview_spp: 64,
        },
        regions: &[
            Region { name: "hair above the light", bounds: [0.3, 0.05, 0.7, 0.35] },
            Region { name: "the light's disc", bounds: [0.45, 0.4, 0.6, 0.55] },
            Region { name: "hair below the light", bounds: [0.3, 0.6, 0.7, 0.95] },
        ],
    },
    Figure {
        id: "fig04",
        title: "Fig. 4: the inner interfaces' Fresnel, f0 against f1 (circular fibre, melanin 1.3)",
        claim: "Using f1 (Eq. 24) instead of f0 changes the TRT lobe's intensity by up to 10 %.",
        work: Work::Render {
            panels: &[
                Panel { scene: "fig04-f0.pbrt", label: "f0 (pbrt-v4's internal Fresnel)", model: Model::Dual },
                Panel { scene: "fig04-f1.pbrt", label: "f1 (Eq. 24)", model: Model::Dual },
            ],
            exposure: 1.0,
            difference: Some((0, 1)),
            difference_scale: 0.2,
            preview_spp: 256,
        },
        regions: &[Region { name: "fibres", bounds: [0.25, 0.1, 0.75, 0.9] }],
    },
    Figure {
        id: "fig07",
        title: "Fig. 7: the diffraction lobe's spectral integral and its logistic fit (a 37.5, b 25 µm, φi 50°)",
        claim: "The spectral integration per channel is close to a single logistic for fibres 50–100 µm thick.",
        work: Work::Plot {
            bcsdf_args: &["--spectral-plot", "--ellipse-a", "37.5", "--ellipse-b", "25"],
            caption: "Red, green, blue channels (left to right) against φr, about ±4° around the forward direction: in colour, the spectral integral of C_diff; in black, the fitted logistic N_diff.",
        },
        regions: &[],
    },
    Figure {
        id: "fig09",
        title: "Fig. 9: white furnace (no absorption, uniform white light)",
        claim: "The dual model passes the white furnace test with and without diffraction.",
        work: Work::Render {
            panels: &[
                Panel { scene: "fig09-reference.pbrt", label: "reference (pbrt-v4 hair)", model: Model::Reference },
                Panel { scene: "fig09-d0.pbrt", label: "dual: a 37.5, b 25 µm, d_diff 0", model: Model::Dual },
                Panel { scene: "fig09-d04.pbrt", label: "dual: d_diff 0.4", model: Model::Dual },
                Panel { scene: "fig09-paper-d04.pbrt", label: "as printed (variant paper), d_diff 0.4", model: Model::Dual },
            ],
            exposure: 0.5,
            difference: None,
            difference_scale: 1.0,
            preview_spp: 64,
        },
        regions: &[Region { name: "the ball", bounds: [0.3, 0.3, 0.7, 0.7] }],
    },
    Figure {
        id: "fig10",
        title: "Fig. 10: the azimuthal scattering function N(φi, φr) per lobe (a 37.5, b 25 µm, θi 0, s 0.01, melanin 0)",
        claim: "The dual model's lobes closely match a full ray-tracing simulation and add the diffraction lobe.",
        work: Work::Plot {
            bcsdf_args: &["--ellipse-a", "37.5", "--ellipse-b", "25", "--logistic-scale", "0.01", "--d-diff", "1", "--diffraction", "logistic"],
            caption: "Left to right: N_R, N_TT, N_TRT, N_diff, and the total with √N_diff as in the paper (blue low, yellow high, each scaled alone); φi across, φr up, 0 to 2π. The dual model only: the paper's top row (a ray-tracing simulation) is not reproduced here.",
        },
        regions: &[],
    },
    Figure {
        id: "fig11",
        title: "Fig. 11: circular against elliptical fibres, no diffraction (melanin 1)",
        claim: "More light is scattered towards the camera when accounting for ellipticity. (The third and fourth panels, not in the paper, turn every fibre's major or minor axis towards the camera's side instead of each strand at random.)",
        work: Work::Render {
            panels: &[
                Panel { scene: "fig11-reference.pbrt", label: "reference (pbrt-v4 hair), melanin 1", model: Model::Reference },
                Panel { scene: "fig11-elliptical.pbrt", label: "dual: a 30, b 20 µm, d_diff 0", model: Model::Dual },
                Panel { scene: "fig11-aligned.pbrt", label: "the same, major axes facing the camera", model: Model::Dual },
                Panel { scene: "fig11-across.pbrt", label: "the same, minor axes facing the camera", model: Model::Dual },
            ],
            exposure: 1.0,
            difference: Some((0, 1)),
            difference_scale: 0.5,
            preview_spp: 64,
        },
        regions: HEAD_REGIONS,
    },
    Figure {
        id: "fig12",
        title: "Fig. 12: backlit dark hair (melanin 8)",
        claim: "Ellipticity alone does not give the forward scattering; d_diff 1 brightens the fibres in front of the light and at the bottom of the hair.",
        work: Work::Render {
            panels: &[
                Panel { scene: "fig12-reference.pbrt", label: "reference (pbrt-v4 hair), melanin 8", model: Model::Reference },
                Panel { scene: "fig12-d0.pbrt", label: "dual: a 30, b 20 µm, d_diff 0", model: Model::Dual },
                Panel { scene: "fig12-d1.pbrt", label: "dual: d_diff 1", model: Model::Dual },
            ],
            exposure: 1.0,
            difference: None,
            difference_scale: 1.0,
            preview_spp: 64,
        },
        regions: &[
            HAIR,
            Region { name: "top edge (against the light)", bounds: [0.3, 0.1, 0.7, 0.25] },
            Region { name: "bottom of the hair", bounds: [0.2, 0.75, 0.8, 0.95] },
        ],
    },
    Figure {
        id: "fig13",
        title: "Fig. 13: fur on the Stanford bunny (melanin 1)",
        claim: "Diffraction lets light deeper into the fur and softens the hard shadows; ellipticity changes the reflections on the side.",
        work: Work::Render {
            panels: &[
                Panel { scene: "fig13-reference.pbrt", label: "reference (pbrt-v4 hair), melanin 1", model: Model::Reference },
                Panel { scene: "fig13-dual.pbrt", label: "dual: a 30, b 20 µm, d_diff 0.2", model: Model::Dual },
            ],
            exposure: 1.0,
            difference: Some((0, 1)),
            difference_scale: 0.5,
            preview_spp: 64,
        },
        regions: &[
            Region { name: "bunny", bounds: [0.25, 0.15, 0.75, 0.85] },
            Region { name: "shadowed side", bounds: [0.25, 0.55, 0.45, 0.8] },
            Region { name: "cast shadow", bounds: [0.69, 0.75, 0.9, 0.87] },
        ],
    },
    Figure {
        id: "fig14",
        title: "Fig. 14: light and camera on the same side (melanin 0.3)",
        claim: "More light is scattered from the top of the hair and the colour changes more smoothly.",
        work: Work::Render {
            panels: &[
                Panel { scene: "fig14-reference.pbrt", label: "reference (pbrt-v4 hair), melanin 0.3", model: Model::Reference },
                Panel { scene: "fig14-dual.pbrt", label: "dual: a 30, b 20 µm, d_diff 0.2", model: Model::Dual },
            ],
            exposure: 1.0,
            difference: Some((0, 1)),
            difference_scale: 0.5,
            preview_spp: 64,
        },
        regions: HEAD_REGIONS,
    },
    Figure {
        id: "fig15",
        title: "Fig. 15: curly hair, light and camera on the same side (melanin 0.3)",
        claim: "As Fig. 14, on another hair style.",
        work: Work::Render {
            panels: &[
                Panel { scene: "fig15-reference.pbrt", label: "reference (pbrt-v4 hair), melanin 0.3", model: Model::Reference },
                Panel { scene: "fig15-dual.pbrt", label: "dual: a 30, b 20 µm, d_diff 0.2", model: Model::Dual },
            ],
            exposure: 1.0,
            difference: Some((0, 1)),
            difference_scale: 0.5,
            preview_spp: 64,
        },
        regions: HEAD_REGIONS,
    },
    Figure {
        id: "fig16",
        title: "Fig. 16: d_diff from 0 to 1 (a 30, b 20 µm, melanin 0.3)",
        claim: "The hair whitens (greys) as d_diff grows; small values (0.2–0.5) already show the diffraction.",
        work: Work::Render {
            panels: &[
                Panel { scene: "fig16-d0.pbrt", label: "d_diff 0", model: Model::Dual },
                Panel { scene: "fig16-d02.pbrt", label: "d_diff 0.2", model: Model::Dual },
                Panel { scene: "fig16-d04.pbrt", label: "d_diff 0.4", model: Model::Dual },
                Panel { scene: "fig16-d06.pbrt", label: "d_diff 0.6", model: Model::Dual },
                Panel { scene: "fig16-d08.pbrt", label: "d_diff 0.8", model: Model::Dual },
                Panel { scene: "fig16-d1.pbrt", label: "d_diff 1", model: Model::Dual },
            ],
            exposure: 1.0,
            difference: None,
            difference_scale: 1.0,
            preview_spp: 64,
        },
        regions: HEAD_REGIONS,
    },
];

macro_rules! scene {
    ($name:literal) => {
        (
            $name,
            include_str!(concat!("../../../pbrt-scenes/paper/", $name)),
        )
    };
}

/// Every file of `pbrt-scenes/paper/` (name, text): the panels' scenes and
/// the cameras, lights and static geometry they include.
pub const SCENE_FILES: &[(&str, &str)] = &[
    scene!("camera-back.pbrt"),
    scene!("camera-head.pbrt"),
    scene!("camera-lock.pbrt"),
    scene!("camera-three-quarter.pbrt"),
    scene!("fibre-arcs.pbrt"),
    scene!("fig01-dual.pbrt"),
    scene!("fig01-reference.pbrt"),
    scene!("fig04-f0.pbrt"),
    scene!("fig04-f1.pbrt"),
    scene!("fig09-d0.pbrt"),
    scene!("fig09-d04.pbrt"),
    scene!("fig09-paper-d04.pbrt"),
    scene!("fig09-reference.pbrt"),
    scene!("fig11-across.pbrt"),
    scene!("fig11-aligned.pbrt"),
    scene!("fig11-elliptical.pbrt"),
    scene!("fig11-reference.pbrt"),
    scene!("fig12-d0.pbrt"),
    scene!("fig12-d1.pbrt"),
    scene!("fig12-reference.pbrt"),
    scene!("fig13-dual.pbrt"),
    scene!("fig13-reference.pbrt"),
    scene!("fig14-dual.pbrt"),
    scene!("fig14-reference.pbrt"),
    scene!("fig15-dual.pbrt"),
    scene!("fig15-reference.pbrt"),
    scene!("fig16-d0.pbrt"),
    scene!("fig16-d02.pbrt"),
    scene!("fig16-d04.pbrt"),
    scene!("fig16-d06.pbrt"),
    scene!("fig16-d08.pbrt"),
    scene!("fig16-d1.pbrt"),
    scene!("lights-behind.pbrt"),
    scene!("lights-front.pbrt"),
    scene!("lights-warm-behind.pbrt"),
];

/// The figure called `id`.
pub fn figure(id: &str) -> Option<&'static Figure> {
    FIGURES.iter().find(|f| f.id == id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_panel_scene_is_built_in_and_every_file_is_used() {
        let mut used = std::collections::HashSet::new();
        for figure in FIGURES {
            if let Work::Render {
                panels, difference, ..
            } = &figure.work
            {
                for panel in *panels {
                    assert!(
                        SCENE_FILES.iter().any(|(name, _)| *name == panel.scene),
                        "{}: {} is not built in",
                        figure.id,
                        panel.scene
                    );
                    used.insert(panel.scene);
                }
                if let Some((a, b)) = difference {
                    assert!(*a < panels.len() && *b < panels.len());
                }
            }
        }
        // Included files are named by some scene.
        for (name, _) in SCENE_FILES {
            let included = SCENE_FILES
                .iter()
                .any(|(_, text)| text.contains(&format!("Include \"{name}\"")));
            assert!(used.contains(name) || included, "{name} is never used");
        }
    }

    #[test]
    fn the_shipped_folder_holds_exactly_the_built_in_files() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("pbrt-scenes/paper");
        let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".pbrt"))
            .collect();
        on_disk.sort();
        let mut built_in: Vec<String> = SCENE_FILES.iter().map(|(n, _)| n.to_string()).collect();
        built_in.sort();
        assert_eq!(on_disk, built_in);
    }
}
