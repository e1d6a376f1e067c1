//! The `obstacles=`, `clearance=` and `no_collide=` keywords of `plan` for an arm (issue 21): the
//! command line's `--obstacle`, `--clearance` and `--no-collide`, over the arm's own shapes.
//!
//! ```python
//! obstacles = [("circle", 0.9, 1.5, 0.1),                 # x, y, r [m]
//!              ("polygon", [0, 0, 0.2, 0, 0.1, 0.3]),     # x1, y1, x2, y2, ... (convex) [m]
//!              "box:1,1,0.2,0.4"]                         # the command line's SPEC
//! no_collide = [("base", "link2")]
//! ```
//!
//! Every form is the command line's spec (`circle:X,Y,R`, `capsule:X1,Y1,X2,Y2,R`,
//! `box:X,Y,W,H`, `polygon:X1,Y1,...`), so the shapes are checked by the library's one reader.

use freefloat::model::InputError;
use freefloat::model::arm::collision::{Body, Geometry};
use freefloat::model::geometry::Shape;
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};

use crate::errors::BindingError;

const EXPECTED: &str = "a list of obstacles, each (\"circle\", x, y, r), (\"capsule\", x1, y1, x2, y2, r), \
                        (\"box\", x, y, w, h), (\"polygon\", [x1, y1, x2, y2, ...]) [m] or a spec string \
                        \"circle:X,Y,R\"";

fn bad(name: String, message: String) -> BindingError {
    BindingError::Key { kind: "invalid_parameter", name, message, expected: EXPECTED }
}

/// The command line's spec of one obstacle item (`name` for messages).
fn spec(name: &str, item: &Bound<'_, PyAny>) -> Result<String, BindingError> {
    if let Ok(text) = item.extract::<String>() {
        return Ok(text);
    }
    let tuple = item.cast::<PyTuple>().map_err(|_| bad(name.into(), "neither a tuple nor a string".into()))?;
    let kind: String = tuple
        .get_item(0)
        .and_then(|k| k.extract())
        .map_err(|_| bad(name.into(), "the first item is not the shape's kind".into()))?;
    let mut numbers = Vec::new();
    for value in tuple.iter().skip(1) {
        match value.extract::<f64>() {
            Ok(x) => numbers.push(x),
            Err(_) => {
                let list: Vec<f64> =
                    value.extract().map_err(|_| bad(name.into(), "an item that is not a number or a list".into()))?;
                numbers.extend(list);
            }
        }
    }
    let numbers: Vec<String> = numbers.iter().map(|x| format!("{x:?}")).collect();
    Ok(format!("{kind}:{}", numbers.join(",")))
}

/// `own` with the keywords applied (obstacles added, the clearance set when given, the pairs
/// excluded), for an arm of `n` joints (checked by `Geometry::validate`).
pub fn apply(
    own: &Geometry,
    n: usize,
    obstacles: Option<&Bound<'_, PyList>>,
    clearance: Option<f64>,
    no_collide: Option<Vec<(String, String)>>,
) -> Result<Geometry, BindingError> {
    let mut out = own.clone();
    for (i, item) in obstacles.into_iter().flat_map(|l| l.iter()).enumerate() {
        let name = format!("obstacles[{i}]");
        let text = spec(&name, &item)?;
        out.obstacles.push(Shape::from_spec(&name, &text)?);
    }
    for (a, b) in no_collide.unwrap_or_default() {
        let body = |text: &str| text.parse::<Body>().map_err(|e| keyword(e, "no_collide"));
        out.excluded.push((body(&a)?, body(&b)?));
    }
    if let Some(c) = clearance {
        out.clearance = c;
    }
    out.validate(n).map_err(|e| match &e {
        InputError::InvalidParameter { name, .. } | InputError::InvalidText { name, .. } => match name.as_str() {
            "--clearance" => keyword(e, "clearance"),
            "--no-collide" => keyword(e, "no_collide"),
            _ => e,
        },
        _ => e,
    })?;
    Ok(out)
}

/// `e` naming the keyword `name` (the library names the command line's flag, or the body).
fn keyword(e: InputError, name: &str) -> InputError {
    match e {
        InputError::InvalidParameter { value, expected, .. } => {
            InputError::InvalidParameter { name: name.into(), value, expected }
        }
        InputError::InvalidText { text, expected, .. } => InputError::InvalidText { name: name.into(), text, expected },
        other => other,
    }
}
