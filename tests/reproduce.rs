//! `rpbrt reproduce` as a user runs it: a draft of a few figures makes the
//! comparison images, the plots and both pages with Table 2; a second run
//! keeps what is there; a different quality renders again; a wrong figure
//! name is refused.
mod common;
use common::rpbrt;

use std::path::PathBuf;

fn temp_dir(name: &str) -> PathBuf {
    common::fresh_dir("reproduce", name)
}

fn read(path: &std::path::Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn a_draft_makes_images_pages_and_table_2_and_resumes() {
    let dir = temp_dir("draft");
    let out = dir.to_str().unwrap();
    let args = [
        "reproduce",
        "--quality",
        "draft",
        "--only",
        "fig13,fig07,fig01",
        "--out",
        out,
    ];
    let first = rpbrt(&args);
    let stderr = String::from_utf8_lossy(&first.stderr);
    assert!(first.status.success(), "{stderr}");

    for file in [
        "fig01.png",
        "fig07.png",
        "fig13.png",
        "index.md",
        "index.html",
    ] {
        assert!(dir.join(file).is_file(), "{file} missing; {stderr}");
    }
    let png = rpbrt::image::Image::read(dir.join("fig01.png")).unwrap();
    // Two 120-pixel panels side by side with gaps: wider than both.
    assert!(png.width() > 240, "{}", png.width());

    let md = read(&dir.join("index.md"));
    // In the paper's order, whatever order --only gave.
    let (f1, f7, f13) = (
        md.find("Fig. 1:").unwrap(),
        md.find("Fig. 7:").unwrap(),
        md.find("Fig. 13:").unwrap(),
    );
    assert!(f1 < f7 && f7 < f13);
    // Table 2 has the two rendered figures with a measured ratio.
    let table = &md[md.find("## Table 2").unwrap()..];
    for fig in ["fig01", "fig13"] {
        let row = table
            .lines()
            .find(|l| l.starts_with(&format!("| {fig} |")))
            .unwrap_or_else(|| panic!("no {fig} row in {table}"));
        assert!(row.ends_with("× |"), "{row}");
    }
    assert!(!md.contains("(kept)"));
    let html = read(&dir.join("index.html"));
    assert!(html.starts_with("<!DOCTYPE html>") && html.contains("<img src=\"fig13.png\""));

    // Each panel has its record, at the requested quality.
    let record = read(&dir.join("fig01/fig01-dual.txt"));
    assert!(
        record.contains("quality draft") && record.contains("spp 4"),
        "{record}"
    );
    // Scene files and geometry are where the scenes include them from.
    assert!(dir.join("scenes/fig13-dual.pbrt").is_file());
    assert!(dir.join("scenes/geometry/bunny-fur.pbrt.gz").is_file());
    assert!(dir.join("scenes/geometry/lock.pbrt.gz").is_file());

    // Again: nothing is rendered, every panel is kept.
    let second = rpbrt(&args);
    assert!(second.status.success());
    let md = read(&dir.join("index.md"));
    assert_eq!(md.matches("(kept)").count(), 4, "{md}");
    assert_eq!(read(&dir.join("fig01/fig01-dual.txt")), record);

    // An unknown figure is refused before anything is done.
    let wrong = rpbrt(&["reproduce", "--only", "fig99", "--out", out]);
    assert!(!wrong.status.success());
    let message = String::from_utf8_lossy(&wrong.stderr);
    assert!(
        message.contains("fig99") && message.contains("fig16"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
