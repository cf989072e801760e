//! `actuator-cam laminate --layup 0/90/0`: ABD matrices, thickness and areal mass of a stack (the thesis'
//! `CFMatrixCalc`).

use super::flags::JsonFlag;
use actuator_cam::design::layup::parse_layup;
use actuator_cam::input::short_number;
use actuator_model::{Laminate, LayerRole, Material};
use anyhow::{anyhow, bail};
use clap::Args;
use nalgebra::Matrix6;
use serde::Serialize;

/// Arguments of `laminate`.
#[derive(Debug, Args)]
pub struct LaminateArgs {
    /// Ply angles bottom to top, e.g. 0/90/0.
    #[arg(long)]
    pub layup: String,
    /// Passive ply material from the built-in library.
    #[arg(long, default_value = "CF-thesis")]
    pub ply: String,
    /// Add a PZT plate of this thickness on each side (mm); without it the passive core alone.
    #[arg(long)]
    pub pzt_thickness_mm: Option<f64>,
    /// PZT material from the built-in library.
    #[arg(long, default_value = "PZT-5H")]
    pub pzt: String,
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
    let layup = parse_layup(&args.layup).map_err(|e| anyhow!("--layup: {e}"))?;
    let ply = Material::builtin(&args.ply)
        .ok_or_else(|| anyhow!("--ply: unknown material {:?}", args.ply))?;
    let t_ply = ply
        .ply_thickness
        .ok_or_else(|| anyhow!("--ply: {} has no standard ply thickness", ply.name))?;
    let laminate = match args.pzt_thickness_mm {
        Some(t) => {
            let allowed = actuator_cam::input::limits::PZT_THICKNESS_MM;
            if !allowed.contains(t) {
                bail!(
                    "--pzt-thickness-mm = {}: outside the {allowed}",
                    short_number(t)
                );
            }
            let pzt = Material::builtin(&args.pzt)
                .ok_or_else(|| anyhow!("--pzt: unknown material {:?}", args.pzt))?;
            Laminate::bimorph(&pzt, t * 1e-3, &ply, t_ply, &layup, None)?
        }
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
        pzt: args.pzt_thickness_mm.map(|_| args.pzt.clone()),
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
        args.layup,
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
