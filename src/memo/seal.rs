//! Content integrity of what the workbench reads back from disk (cache entries, shard
//! files): a JSON object carries the SHA-256 of its own canonical content, the object's
//! compact serialisation with keys in sorted order and the `sha256` field left out
//! (floats in their shortest round-trip form, so reading and writing again gives the same
//! text). Any change of content (a digit, a sign, an exponent, a key, the structure)
//! changes the digest; a file whose digest does not match is not used.

use serde_json::Value;
use sha2::{Digest, Sha256};

/// The field that holds the digest.
pub const FIELD: &str = "sha256";

fn digest(v: &Value) -> String {
    let text = serde_json::to_string(v).unwrap_or_default();
    Sha256::digest(text.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// `v` (an object) with the digest of its content added.
pub fn seal(mut v: Value) -> Value {
    if let Some(o) = v.as_object_mut() {
        o.remove(FIELD);
    }
    let d = digest(&v);
    if let Some(o) = v.as_object_mut() {
        o.insert(FIELD.into(), Value::String(d));
    }
    v
}

/// The content of a sealed object, if its digest matches; otherwise why not (one line).
pub fn open(mut v: Value) -> Result<Value, String> {
    let o = v
        .as_object_mut()
        .ok_or_else(|| "not a JSON object".to_string())?;
    let claimed = match o.remove(FIELD) {
        Some(Value::String(s)) => s,
        Some(_) => return Err(format!("its {FIELD} field is not a string")),
        None => return Err(format!("it carries no {FIELD} of its content")),
    };
    let actual = digest(&v);
    if actual == claimed {
        Ok(v)
    } else {
        Err(format!(
            "its content does not match its SHA-256 (stored {}…, content {}…)",
            &claimed.chars().take(12).collect::<String>(),
            &actual[..12]
        ))
    }
}
