//! Writes sample figures from synthetic data: `cargo run -p objmodel-plot --example samples -- DIR`
//! (default `target/objmodel-plot-samples`).

#[path = "../tests/synthetic/mod.rs"]
mod synthetic;

use std::path::PathBuf;

fn main() -> Result<(), objmodel_plot::PlotError> {
    let dir = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("target/objmodel-plot-samples"));
    let outputs = [
        objmodel_plot::plot_angles(&synthetic::fig8(), &dir.join("fig8_angles"))?,
        objmodel_plot::plot_side_view(&synthetic::side_view(), &dir.join("fig5_side_view"))?,
        objmodel_plot::plot_xy(
            "Generic x-y plot",
            "x [m]",
            "y [m]",
            &synthetic::xy_series(),
            &dir.join("xy"),
        )?,
    ];
    for (svg, png) in outputs {
        println!("{}\n{}", svg.display(), png.display());
    }
    Ok(())
}
