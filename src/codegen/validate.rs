//! Every generated WGSL module passes naga's parser and validator before it is written.

use crate::error::{Error, Result};

/// Parse and validate generated WGSL with naga; a failure is a typed error naming `what`.
pub fn validate_wgsl(src: &str, what: &str) -> Result<()> {
    let module = naga::front::wgsl::parse_str(src).map_err(|e| {
        Error::InvalidArgument(format!(
            "{what}: generated WGSL does not parse: {}",
            e.message()
        ))
    })?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| {
        Error::InvalidArgument(format!(
            "{what}: generated WGSL does not validate: {}",
            e.as_inner()
        ))
    })?;
    Ok(())
}
