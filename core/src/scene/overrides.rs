//! `--set KEY=VALUE` overrides: KEY is a TOML path into the scene (`drop.velocity_amplitude`,
//! `phases.0.mu` or `phases[0].mu`), VALUE any TOML value (a bare word is taken as a string).
//! The edited scene is re-read with unknown fields denied, so a misspelt key is an error.

use super::{Scene, SceneError};
use toml::Value;

fn err(field: &str, msg: impl Into<String>) -> SceneError {
    SceneError { field: field.to_string(), msg: msg.into() }
}

fn parse_value(text: &str) -> Value {
    match toml::from_str::<toml::Table>(&format!("v = {text}")) {
        Ok(mut t) => t.remove("v").unwrap_or(Value::String(text.to_string())),
        Err(_) => Value::String(text.to_string()),
    }
}

fn split_path(key: &str) -> Vec<String> {
    key.replace('[', ".").replace(']', "").split('.').filter(|s| !s.is_empty()).map(str::to_string).collect()
}

fn set_path(root: &mut Value, path: &[String], value: Value, key: &str) -> Result<(), SceneError> {
    let (head, rest) = path.split_first().ok_or_else(|| err(key, "empty key"))?;
    match root {
        Value::Table(t) => {
            if rest.is_empty() {
                t.insert(head.clone(), value);
                Ok(())
            } else {
                let child = t.entry(head.clone()).or_insert_with(|| Value::Table(Default::default()));
                set_path(child, rest, value, key)
            }
        }
        Value::Array(a) => {
            let i: usize = head.parse().map_err(|_| err(key, format!("`{head}` is not an index into a list")))?;
            let len = a.len();
            let slot = a.get_mut(i).ok_or_else(|| err(key, format!("index {i} out of range (the list has {len})")))?;
            if rest.is_empty() {
                *slot = value;
                Ok(())
            } else {
                set_path(slot, rest, value, key)
            }
        }
        _ => Err(err(key, format!("`{head}` is inside a value that is not a table"))),
    }
}

/// Applies `KEY=VALUE` overrides in order and validates the result.
pub fn apply_overrides(scene: &Scene, sets: &[String]) -> Result<Scene, SceneError> {
    if sets.is_empty() {
        return Ok(scene.clone());
    }
    let mut root = Value::try_from(scene).map_err(|e| err("<scene>", e.to_string()))?;
    for s in sets {
        let (key, val) = s.split_once('=').ok_or_else(|| err(s, "expected KEY=VALUE"))?;
        let key = key.trim();
        let path = split_path(key);
        set_path(&mut root, &path, parse_value(val.trim()), key)?;
        // Re-read after each override so the error names this key.
        let text = toml::to_string(&root).map_err(|e| err(key, e.to_string()))?;
        toml::from_str::<Scene>(&text).map_err(|e| err(key, e.message().to_string()))?;
    }
    let text = toml::to_string(&root).map_err(|e| err("<scene>", e.to_string()))?;
    let mut out: Scene = toml::from_str(&text).map_err(|e| err("<scene>", e.message().to_string()))?;
    // The capillary rule follows the resolution and kernel set here, except where a p_b or c0
    // is set by name.
    // Without surface tension there is no band tension: the rule does not apply, and p_b and
    // c0 stay the scene's.
    if out.surface_tension.as_ref().is_some_and(|t| t.sigma == 0.0) {
        out.capillary_rule = None;
    }
    super::validate::capillary_rule(&out)?;
    if out.capillary_rule.is_some() {
        super::validate::rule_inputs(&out)?;
        let named: Vec<&str> = sets.iter().filter_map(|s| s.split_once('=')).map(|(k, _)| k.trim()).collect();
        let ruled = super::capillary::ruled(&out);
        for (k, (p, r)) in out.phases.iter_mut().zip(ruled.phases).enumerate() {
            if !named.contains(&format!("phases.{k}.p_b").as_str()) {
                p.p_b = r.p_b;
            }
            if !named.contains(&format!("phases.{k}.c0").as_str()) {
                p.c0 = r.c0;
            }
        }
    }
    out.validate()?;
    Ok(out)
}
