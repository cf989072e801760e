//! `actuator-cam laminate --layup 0/90/0`: ABD matrices, thickness and areal mass of a stack (the thesis'
//! `CFMatrixCalc`).

use super::flags::{self, JsonFlag, Layup};
use actuator_model::{Laminate, LayerRole, Material};
use clap::Args;
use nalgebra::Matrix6;
use serde::Serialize;

/// Arguments of `laminate`.
#[derive(Debug, Args)]
pub struct LaminateArgs {
    /// Ply angles bottom to top, e.g. 0/90/0.
    #[arg(long, value_name = "ANGLES", value_parser = flags::layup)]
    pub layup: Layup,
    /// Passive ply material from the built-in library (one with a standard ply thickness).
    #[arg(long, value_name = "NAME", default_value = "CF-thesis", value_parser = flags::ply_material)]
    pub ply: Material,
    /// Add a PZT plate of this thickness on each side (mm); without it the passive core alone.
    #[arg(long, value_name = "MM", value_parser = flags::pzt_thickness_mm)]
    pub pzt_thickness_mm: Option<f64>,
    /// PZT material from the built-in library.
    #[arg(long, value_name = "NAME", default_value = "PZT-5H", value_parser = flags::material)]
    pub pzt: Material,
    /// `--json`.
    #[command(flatten)]
    pub json: JsonFlag,
}

#[derive(Serialize)]
#[allow(non_snake_case)]
struct LaminateReport {
    layup_deg: Vec<f64>,
    ply: String,
    pzt: Option<String>,
    pzt_thickness_mm: Option<f64>,
    thickness_mm: f64,
    areal_mass_g_per_m2: f64,
    passive_areal_mass_g_per_m2: f64,
    A_N_per_m: [[f64; 3]; 3],
    B_N: [[f64; 3]; 3],
    D_N_m: [[f64; 3]; 3],
    bending_compliance_C44_per_N_m: f64,
}

fn block(m: &Matrix6<f64>, r: usize, c: usize) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = m[(r + i, c + j)];
        }
    }
    out
}

/// Run `laminate`.
pub fn run(args: &LaminateArgs) -> anyhow::Result<()> {
    let layup = args.layup.angles.clone();
    let ply = &args.ply;
    // The parser took only a ply with a standard thickness.
    let t_ply = ply.ply_thickness.unwrap_or_default();
    let laminate = match args.pzt_thickness_mm {
        Some(t) => Laminate::bimorph(&args.pzt, t * 1e-3, ply, t_ply, &layup, None)?,
        None => Laminate::new(
            layup
                .iter()
                .map(|&angle_deg| actuator_model::Layer {
                    material: ply.clone(),
                    thickness: t_ply,
                    angle_deg,
                    role: LayerRole::Passive,
                })
                .collect(),
        )?,
    };
    let abd = laminate.abd();
    let total_areal: f64 = [
        LayerRole::Piezo,
        LayerRole::InactivePiezo,
        LayerRole::Passive,
        LayerRole::Bond,
    ]
    .iter()
    .map(|r| laminate.areal_mass(*r))
    .sum();
    let report = LaminateReport {
        layup_deg: layup,
        ply: ply.name.clone(),
        pzt: args.pzt_thickness_mm.map(|_| args.pzt.name.clone()),
        pzt_thickness_mm: args.pzt_thickness_mm,
        thickness_mm: laminate.thickness() * 1e3,
        areal_mass_g_per_m2: total_areal * 1e3,
        passive_areal_mass_g_per_m2: laminate.areal_mass(LayerRole::Passive) * 1e3,
        A_N_per_m: block(abd, 0, 0),
        B_N: block(abd, 0, 3),
        D_N_m: block(abd, 3, 3),
        bending_compliance_C44_per_N_m: laminate.bending_compliance(),
    };
    if args.json.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    println!(
        "layup {} of {}{}",
        args.layup.text,
        report.ply,
        match (&report.pzt, report.pzt_thickness_mm) {
            (Some(p), Some(t)) => format!(", with {t} mm {p} on each side"),
            _ => String::new(),
        }
    );
    println!(
        "thickness {:.4} mm, areal mass {:.2} g/m² (passive {:.2} g/m²)",
        report.thickness_mm, report.areal_mass_g_per_m2, report.passive_areal_mass_g_per_m2
    );
    for (name, unit, m) in [
        ("A", "N/m", report.A_N_per_m),
        ("B", "N", report.B_N),
        ("D", "N·m", report.D_N_m),
    ] {
        println!("{name} ({unit}):");
        for row in m {
            println!("  {:>14.6e} {:>14.6e} {:>14.6e}", row[0], row[1], row[2]);
        }
    }
    println!(
        "C44 (bending compliance) {:.6e} 1/(N·m)",
        report.bending_compliance_C44_per_N_m
    );
    Ok(())
}
