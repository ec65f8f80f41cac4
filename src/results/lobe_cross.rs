//! The cross study's result (results/fits/ltc-lobe-cross.json): each LTC table family's
//! tables judged against the other lobe's, and the clamped cosine and a bounded table
//! against the main lobe.

use super::ltc::Located;
use crate::fit::spec::FitSpec;
use serde::{Deserialize, Serialize};

/// results/fits/ltc-lobe-cross.json: each table family's tables judged against the other
/// lobe's, and the clamped cosine and a bounded table against the main lobe.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LobeCross {
    pub spec: FitSpec,
    pub command: String,
    pub preset: String,
    pub families: Vec<FamilyCross>,
}

impl super::ResultFile for LobeCross {
    const NAME: &'static str = super::names::LTC_LOBE_CROSS;
}

/// One family's cross judgements (every cell of its grid).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FamilyCross {
    pub family: String,
    /// The result names of the main table and of the variant's.
    pub main_table: String,
    pub variant_table: String,
    /// The two tables' fingerprints (`FittedTable::fingerprint`), main first.
    pub fingerprints: [String; 2],
    /// The main table against the variant's lobe.
    pub main_table_for_variant: Located,
    /// The variant's table against the main lobe.
    pub variant_table_for_main: Located,
    /// The clamped cosine (M = I) with weight 1 against the main lobe.
    pub cosine_unit_for_main: Located,
    /// The clamped cosine with the main table's norm (energy-correct Lambert).
    pub cosine_norm_for_main: Located,
    /// Where the main table's albedo exceeds 1 (`None` where it nowhere does).
    pub bounded: Option<Bounded>,
}

/// The main table with its norm clamped to ≤ 1 on the cells whose albedo exceeds 1, and
/// the true table on the same cells.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Bounded {
    pub cells: usize,
    pub bounded: Located,
    pub true_table: Located,
}
