//! The named lobes LTC tables are fitted to, as one target type: the GGX specular lobe
//! (Heitz et al. 2016), the Charlie sheen lobe with either visibility term (Estevez &
//! Kulla 2017's fitted Λ, or Neubelt & Pettineo 2013's, which glTF's KHR_materials_sheen
//! names as the cheap alternative and three.js and Filament ship) and Burley's diffuse
//! (Burley 2012 §5.3) with either roughness convention in F_D90. A study picks a lobe
//! by name and fits, reports and writes it like any other target.

use super::diffuse::{BurleyRoughness, BurleyTarget};
use super::sheen::{CharlieTarget, SheenVisibility};
use super::target::{GgxTarget, LtcTarget};
use crate::error::Result;
use nalgebra::Vector3;

type V3 = Vector3<f64>;

/// A lobe a table can be fitted to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Lobe {
    Ggx,
    SheenEstevezKulla,
    SheenNeubelt,
    BurleyPaper,
    BurleyEngines,
}

/// A table family: the lobe of its main table and of its variant (the ltc-sheen and
/// ltc-diffuse studies fit both; the ltc-lobe-cross study shades each with the other's
/// table).
#[derive(Clone, Copy, Debug)]
pub struct Family {
    pub name: &'static str,
    pub title: &'static str,
    pub main: Lobe,
    pub variant: Lobe,
    /// The spec name of the variant's table (results/fits/<variant_name>.json).
    pub variant_name: &'static str,
}

/// The families, by spec name.
pub fn family(name: &str) -> Option<Family> {
    match name {
        "ltc-sheen" => Some(Family {
            name: "ltc-sheen",
            title: "Charlie sheen LTC tables",
            main: Lobe::SheenEstevezKulla,
            variant: Lobe::SheenNeubelt,
            variant_name: "ltc-sheen-neubelt",
        }),
        "ltc-diffuse" => Some(Family {
            name: "ltc-diffuse",
            title: "Burley diffuse LTC tables",
            main: Lobe::BurleyPaper,
            variant: Lobe::BurleyEngines,
            variant_name: "ltc-diffuse-engines",
        }),
        _ => None,
    }
}

impl Lobe {
    /// The target of cell (α, θ).
    pub fn target(self, alpha: f64, theta: f64) -> Result<LobeTarget> {
        Ok(match self {
            Lobe::Ggx => LobeTarget::Ggx(Box::new(GgxTarget::new(alpha, theta)?)),
            Lobe::SheenEstevezKulla => LobeTarget::Charlie(CharlieTarget::new(
                alpha,
                theta,
                SheenVisibility::EstevezKulla,
            )?),
            Lobe::SheenNeubelt => {
                LobeTarget::Charlie(CharlieTarget::new(alpha, theta, SheenVisibility::Neubelt)?)
            }
            Lobe::BurleyPaper => {
                LobeTarget::Burley(BurleyTarget::new(alpha, theta, BurleyRoughness::Paper)?)
            }
            Lobe::BurleyEngines => {
                LobeTarget::Burley(BurleyTarget::new(alpha, theta, BurleyRoughness::Engines)?)
            }
        })
    }
    /// What the lobe is, in one phrase, with its source.
    pub fn describe(self) -> &'static str {
        match self {
            Lobe::Ggx => "GGX, height-correlated Smith G2, F = 1 (Heitz et al. 2016)",
            Lobe::SheenEstevezKulla => "Charlie sheen NDF with Estevez & Kulla 2017's height-correlated visibility from their fitted Λ (the form glTF's KHR_materials_sheen specifies), F = 1",
            Lobe::SheenNeubelt => "Charlie sheen NDF with Neubelt & Pettineo 2013's visibility 1/(4(l_z + v_z − l_z v_z)) (three.js's and Filament's V_Neubelt), F = 1",
            Lobe::BurleyPaper => "Burley 2012 diffuse with its retro-reflection term, F_D90 = ½ + 2 r cos²θ_d with the paper's (perceptual) roughness r = √α, albedo 1",
            Lobe::BurleyEngines => "Burley 2012 diffuse as Filament and Bevy evaluate it, F_D90 = ½ + 2 α cos²θ_d with α = r², albedo 1",
        }
    }
    /// Why the lobe's albedo can exceed 1, in one phrase.
    pub fn why_above_one(self) -> &'static str {
        match self {
            Lobe::Ggx => "a microfacet BRDF with a Smith G2 does not exceed 1",
            Lobe::SheenEstevezKulla => "Estevez & Kulla's Λ is a fit, not the Smith Λ of the Charlie NDF, so the BRDF it makes does not conserve energy; the excess is largest at small α and grazing views",
            Lobe::SheenNeubelt => "Neubelt & Pettineo's visibility 1/(4(l_z + v_z − l_z v_z)) is no masking term: it stays finite as l_z and v_z → 0 while the Charlie NDF piles its mass at grazing half-vectors",
            Lobe::BurleyPaper | Lobe::BurleyEngines => "Burley's retro-reflection factor with F_D90 up to 2.5 is an empirical fit that does not conserve energy (Burley 2012 §5.3)",
        }
    }
    /// A short name for tables and file names.
    pub fn short(self) -> &'static str {
        match self {
            Lobe::Ggx => "GGX",
            Lobe::SheenEstevezKulla => "Charlie, Estevez–Kulla Λ",
            Lobe::SheenNeubelt => "Charlie, Neubelt visibility",
            Lobe::BurleyPaper => "Burley, paper's roughness",
            Lobe::BurleyEngines => "Burley, engines' α",
        }
    }
}

/// The target of one cell of any [`Lobe`].
pub enum LobeTarget {
    Ggx(Box<GgxTarget>),
    Charlie(CharlieTarget),
    Burley(BurleyTarget),
}

impl LobeTarget {
    fn inner(&self) -> &dyn LtcTarget {
        match self {
            LobeTarget::Ggx(t) => t.as_ref(),
            LobeTarget::Charlie(t) => t,
            LobeTarget::Burley(t) => t,
        }
    }
}

impl LtcTarget for LobeTarget {
    fn view(&self) -> V3 {
        self.inner().view()
    }
    fn eval(&self, l: &V3) -> (f64, f64) {
        self.inner().eval(l)
    }
    fn eval_lanes(
        &self,
        l: &crate::lanes::Dirs,
        live: [bool; crate::lanes::LANES],
    ) -> [(f64, f64); crate::lanes::LANES] {
        self.inner().eval_lanes(l, live)
    }
    fn sample(&self, u: [f64; 2]) -> Option<V3> {
        self.inner().sample(u)
    }
    fn width(&self) -> f64 {
        self.inner().width()
    }
    fn albedo(&self, tol: f64) -> (f64, f64, f64) {
        self.inner().albedo(tol)
    }
    fn chart(&self) -> super::chart::Chart {
        self.inner().chart()
    }
}
