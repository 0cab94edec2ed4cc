//! Stone outlines from SVG: `<polygon>`, closed `<polyline>`, `<rect>` and `<path>` (M, L,
//! H, V, Z, absolute and relative), each under the `transform`s of its groups and its own,
//! in user units of the root; y down in the drawing, z up in the wall. Elements inside
//! `<defs>`, `<clipPath>`, `<mask>`, `<pattern>`, `<symbol>`, `<marker>` and `<metadata>`,
//! hidden ones (`display` none, a hidden layer), and elements with a `data-ignore`
//! attribute (on themselves or a group around them) are not stones; one drawn
//! `<line id="scale" data-length-m="L">` (ignored or not; a second is refused) gives the
//! scale; `<circle>`, `<ellipse>` and `<use>` (a clone) are refused (a stone is a polygon).

use super::{Outline, Stone, SurveyError};
use std::path::Path;

/// An affine map `x' = a x + c y + e`, `y' = b x + d y + f`, as SVG's `matrix(a b c d e f)`.
type Affine = [f64; 6];

const IDENTITY: Affine = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0];

/// Containers whose content is not drawn as it stands.
const NOT_DRAWN: [&str; 7] = ["defs", "clipPath", "mask", "pattern", "symbol", "marker", "metadata"];

/// The outlines of the SVG document `text` read from `path`, in metres (x along the wall, z
/// up, before the translation to the table), and the scale used with where it came from.
pub(super) fn read(path: &Path, text: &str, scale: Option<f64>) -> Result<(Vec<Outline>, (f64, String)), SurveyError> {
    let options = roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() };
    let doc = roxmltree::Document::parse_with_options(text, options)
        .map_err(|e| SurveyError::File { path: path.to_owned(), reason: format!("not valid XML: {e}") })?;
    if doc.root_element().tag_name().name() != "svg" {
        return Err(SurveyError::File { path: path.to_owned(), reason: "the root element is not <svg>".into() });
    }
    let mut shapes: Vec<(Stone, Vec<[f64; 2]>)> = Vec::new();
    let mut scale_line: Option<(f64, String)> = None;
    for node in doc.descendants().filter(|n| n.is_element()) {
        let tag = node.tag_name().name();
        let scale_line_here = tag == "line" && node.attribute("id") == Some("scale") && !not_drawn(node);
        let outline = ["polygon", "polyline", "rect", "path", "circle", "ellipse", "use"].contains(&tag);
        if !scale_line_here && (!outline || ignored(node)) {
            continue;
        }
        let element = describe(&doc, node);
        let err = |reason: String| SurveyError::Element { path: path.to_owned(), element: element.clone(), reason };
        let m = transform_of(node).map_err(err)?;
        if scale_line_here {
            if let Some((_, first)) = &scale_line {
                return Err(err(format!(
                    "a second scale line (the first is {first}): a drawing has one <line id=\"scale\">"
                )));
            }
            scale_line = Some(scale_from_line(node, &m).map_err(err)?);
            continue;
        }
        if tag == "use" {
            return Err(err("<use> (a clone) is not read: turn clones into paths in the drawing program (unlink the \
                 clone), or mark it data-ignore"
                .into()));
        }
        let points = match tag {
            "polygon" => parse_points(node.attribute("points").unwrap_or("")).map_err(err)?,
            "polyline" => closed_polyline(node).map_err(err)?,
            "rect" => rect(node).map_err(err)?,
            "path" => path_outline(node.attribute("d").unwrap_or("")).map_err(err)?,
            _ => {
                return Err(err(format!(
                    "<{tag}> is not an outline: trace stones as polygons or paths of straight segments (or mark it \
                     data-ignore)"
                )))
            }
        };
        let points: Vec<[f64; 2]> = points.iter().map(|p| apply(&m, *p)).collect();
        let id = node
            .attribute("id")
            .filter(|h| !h.trim().is_empty())
            .map_or_else(|| format!("s{}", shapes.len()), str::to_owned);
        let material = node.ancestors().find_map(|a| a.attribute("data-material")).map(str::to_owned);
        let depth_m = match node.ancestors().find_map(|a| a.attribute("data-depth-m")) {
            None => None,
            Some(t) => Some(
                t.trim().parse::<f64>().map_err(|_| err(format!("data-depth-m {t:?} is not a number of metres")))?,
            ),
        };
        shapes.push((Stone { id, element, material, depth_m }, points));
    }
    let scale = match (scale, scale_line) {
        (Some(s), Some(_)) => (s, "--scale-m-per-unit (the scale line is not used)".to_string()),
        (Some(s), None) => (s, "--scale-m-per-unit".to_string()),
        (None, Some((s, element))) => (s, format!("the scale line {element}")),
        (None, None) => {
            return Err(SurveyError::File {
                path: path.to_owned(),
                reason: "no scale: give --scale-m-per-unit (metres per user unit), or draw a <line id=\"scale\" \
                         data-length-m=\"…\"> of a known length"
                    .into(),
            })
        }
    };
    let outlines = shapes
        .into_iter()
        .map(|(stone, pts)| Outline { stone, points: pts.iter().map(|p| [p[0] * scale.0, -p[1] * scale.0]).collect() })
        .collect();
    Ok((outlines, scale))
}

/// `<tag id="…"> at line N`.
fn describe(doc: &roxmltree::Document, node: roxmltree::Node) -> String {
    let line = doc.text_pos_at(node.range().start).row;
    match node.attribute("id") {
        Some(id) => format!("<{} id=\"{id}\"> at line {line}", node.tag_name().name()),
        None => format!("<{}> at line {line}", node.tag_name().name()),
    }
}

/// Whether the element is inside a container whose content is not drawn as it stands
/// ([`NOT_DRAWN`]), or hidden (`display="none"` or `display:none` in its `style`, on itself
/// or a group around it: a hidden layer).
fn not_drawn(node: roxmltree::Node) -> bool {
    node.ancestors().any(|a| {
        NOT_DRAWN.contains(&a.tag_name().name())
            || a.attribute("display").is_some_and(|d| d.trim() == "none")
            || a.attribute("style").is_some_and(|st| {
                st.split(';').any(|d| {
                    let mut kv = d.splitn(2, ':');
                    kv.next().map(str::trim) == Some("display") && kv.next().map(str::trim) == Some("none")
                })
            })
    })
}

/// Whether the element is not drawn ([`not_drawn`]) or is marked `data-ignore`.
fn ignored(node: roxmltree::Node) -> bool {
    not_drawn(node) || node.ancestors().any(|a| a.attribute("data-ignore").is_some())
}

/// The element's transform composed with its ancestors' (outermost first).
fn transform_of(node: roxmltree::Node) -> Result<Affine, String> {
    let mut chain: Vec<roxmltree::Node> = node.ancestors().filter(|a| a.attribute("transform").is_some()).collect();
    chain.reverse();
    let mut m = IDENTITY;
    for a in chain {
        let t = parse_transform(a.attribute("transform").unwrap_or("")).map_err(|e| {
            let whose = if a == node { "its".to_string() } else { format!("its group's ({})", a.tag_name().name()) };
            format!("{whose} transform: {e}")
        })?;
        m = compose(&m, &t);
    }
    Ok(m)
}

/// `m ∘ t`: t applied first.
fn compose(m: &Affine, t: &Affine) -> Affine {
    [
        m[0] * t[0] + m[2] * t[1],
        m[1] * t[0] + m[3] * t[1],
        m[0] * t[2] + m[2] * t[3],
        m[1] * t[2] + m[3] * t[3],
        m[0] * t[4] + m[2] * t[5] + m[4],
        m[1] * t[4] + m[3] * t[5] + m[5],
    ]
}

fn apply(m: &Affine, p: [f64; 2]) -> [f64; 2] {
    if *m == IDENTITY {
        return p;
    }
    [m[0] * p[0] + m[2] * p[1] + m[4], m[1] * p[0] + m[3] * p[1] + m[5]]
}

/// An SVG transform list: `matrix`, `translate`, `scale`, `rotate` (degrees, with an
/// optional centre), `skewX`, `skewY`.
fn parse_transform(text: &str) -> Result<Affine, String> {
    let mut m = IDENTITY;
    let mut rest = text.trim_start_matches(|c: char| c.is_whitespace() || c == ',');
    while !rest.is_empty() {
        let open = rest.find('(').ok_or_else(|| format!("{text:?}: expected `name(…)`"))?;
        let close = open + rest[open..].find(')').ok_or_else(|| format!("{text:?}: a `(` without its `)`"))?;
        let name = rest[..open].trim();
        let mut s = Scanner::new(&rest[open + 1..close]);
        let mut args = Vec::new();
        while let Some(v) = s.number()? {
            args.push(v);
        }
        let bad = || {
            format!(
                "{name}({}): wrong number of values",
                args.iter().map(|a| a.to_string()).collect::<Vec<_>>().join(" ")
            )
        };
        let t = match (name, args.as_slice()) {
            ("matrix", &[a, b, c, d, e, f]) => [a, b, c, d, e, f],
            ("translate", &[x]) => [1.0, 0.0, 0.0, 1.0, x, 0.0],
            ("translate", &[x, y]) => [1.0, 0.0, 0.0, 1.0, x, y],
            ("scale", &[k]) => [k, 0.0, 0.0, k, 0.0, 0.0],
            ("scale", &[kx, ky]) => [kx, 0.0, 0.0, ky, 0.0, 0.0],
            ("rotate", &[a]) => rotation(a),
            ("rotate", &[a, cx, cy]) => {
                let t = compose(&[1.0, 0.0, 0.0, 1.0, cx, cy], &rotation(a));
                compose(&t, &[1.0, 0.0, 0.0, 1.0, -cx, -cy])
            }
            ("skewX", &[a]) => [1.0, 0.0, a.to_radians().tan(), 1.0, 0.0, 0.0],
            ("skewY", &[a]) => [1.0, a.to_radians().tan(), 0.0, 1.0, 0.0, 0.0],
            ("matrix" | "translate" | "scale" | "rotate" | "skewX" | "skewY", _) => return Err(bad()),
            _ => return Err(format!("unknown transform {name:?}")),
        };
        m = compose(&m, &t);
        rest = rest[close + 1..].trim_start_matches(|c: char| c.is_whitespace() || c == ',');
    }
    Ok(m)
}

fn rotation(deg: f64) -> Affine {
    let (s, c) = deg.to_radians().sin_cos();
    [c, s, -s, c, 0.0, 0.0]
}

/// The scale of `<line id="scale" data-length-m="L">`: L over the line's length in user
/// units, m per unit.
fn scale_from_line(node: roxmltree::Node, m: &Affine) -> Result<(f64, String), String> {
    let coord = |k: &str| length(node, k, Some(0.0));
    let (a, b) = ([coord("x1")?, coord("y1")?], [coord("x2")?, coord("y2")?]);
    let (a, b) = (apply(m, a), apply(m, b));
    let units = (b[0] - a[0]).hypot(b[1] - a[1]);
    let text = node.attribute("data-length-m").ok_or("the scale line needs data-length-m (its length in metres)")?;
    let metres: f64 = text.trim().parse().map_err(|_| format!("data-length-m = {text:?} is not a number"))?;
    if !(metres.is_finite() && metres > 0.0 && units > 0.0) {
        return Err(format!("the scale line is {units} units long for {metres} m: both must be positive"));
    }
    let line = node.document().text_pos_at(node.range().start).row;
    Ok((metres / units, format!("at line {line} ({metres} m over {units} units)")))
}

/// A numeric attribute in user units (a number, or a number with `px`); `default` when
/// absent (None: required).
fn length(node: roxmltree::Node, key: &str, default: Option<f64>) -> Result<f64, String> {
    let Some(text) = node.attribute(key) else {
        return default.ok_or_else(|| format!("no {key} attribute"));
    };
    let t = text.trim();
    let t = t.strip_suffix("px").unwrap_or(t);
    match t.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("{key} = {text:?} is not a number of user units (no unit but px)")),
    }
}

fn rect(node: roxmltree::Node) -> Result<Vec<[f64; 2]>, String> {
    let (x, y) = (length(node, "x", Some(0.0))?, length(node, "y", Some(0.0))?);
    let (w, h) = (length(node, "width", None)?, length(node, "height", None)?);
    if !(w > 0.0 && h > 0.0) {
        return Err(format!("width {w} and height {h} must be positive"));
    }
    if length(node, "rx", Some(0.0))? != 0.0 || length(node, "ry", Some(0.0))? != 0.0 {
        return Err("rounded corners (rx, ry) are not a polygon".into());
    }
    Ok(vec![[x, y], [x + w, y], [x + w, y + h], [x, y + h]])
}

/// The pairs of a `points` attribute.
fn parse_points(text: &str) -> Result<Vec<[f64; 2]>, String> {
    let mut s = Scanner::new(text);
    let mut v = Vec::new();
    while let Some(x) = s.number()? {
        let y =
            s.number()?.ok_or_else(|| format!("points: an odd number of coordinates ({} pairs and one)", v.len()))?;
        v.push([x, y]);
    }
    // `number` stops before a letter (a path's next command); a `points` list has none, so
    // a word among its numbers (`nan`, `inf`, a unit) is refused, not read as its end.
    if !s.at_end() {
        let rest = String::from_utf8_lossy(&s.s[s.i..]);
        let word: String = rest.chars().take_while(|c| !c.is_whitespace() && *c != ',').collect();
        return Err(format!("points: {word:?} at character {} is not a number", s.i + 1));
    }
    Ok(v)
}

/// A polyline's points if it closes (its last point is its first).
fn closed_polyline(node: roxmltree::Node) -> Result<Vec<[f64; 2]>, String> {
    let mut pts = parse_points(node.attribute("points").unwrap_or(""))?;
    match (pts.first(), pts.last()) {
        (Some(a), Some(b)) if pts.len() > 3 && a == b => {
            pts.pop();
            Ok(pts)
        }
        _ => Err("a polyline is a stone only if it closes (its last point equals its first)".into()),
    }
}

/// The one closed outline of path data `d`: M, L, H, V, Z (and their relative forms); a
/// subpath ends closed by Z or on its first point; curves and arcs are refused.
fn path_outline(d: &str) -> Result<Vec<[f64; 2]>, String> {
    let mut s = Scanner::new(d);
    let mut subpaths: Vec<(Vec<[f64; 2]>, bool)> = Vec::new();
    let (mut cur, mut start) = ([0.0, 0.0], [0.0, 0.0]);
    let mut cmd: Option<char> = None;
    loop {
        let c = match s.command() {
            Some(c) => c,
            None if s.at_end() => break,
            None => cmd.ok_or("path data must start with M")?,
        };
        let rel = c.is_ascii_lowercase();
        let off = |p: [f64; 2], cur: [f64; 2]| if rel { [p[0] + cur[0], p[1] + cur[1]] } else { p };
        match c.to_ascii_uppercase() {
            'M' => {
                let p = off(s.pair()?, cur);
                subpaths.push((vec![p], false));
                (cur, start) = (p, p);
                cmd = Some(if rel { 'l' } else { 'L' });
                continue;
            }
            'L' => cur = off(s.pair()?, cur),
            'H' => cur[0] = s.required()? + if rel { cur[0] } else { 0.0 },
            'V' => cur[1] = s.required()? + if rel { cur[1] } else { 0.0 },
            'Z' => {
                let last = subpaths.last_mut().ok_or("Z before any M")?;
                last.1 = true;
                cur = start;
                cmd = None;
                continue;
            }
            other => {
                return Err(format!(
                    "path command {other:?} (curve or arc) is not supported: a stone outline is straight segments \
                     (M, L, H, V, Z)"
                ))
            }
        }
        subpaths.last_mut().ok_or("path data must start with M")?.0.push(cur);
        cmd = Some(c);
    }
    subpaths.retain(|(p, _)| p.len() > 1);
    match subpaths.as_mut_slice() {
        [(pts, closed)] => {
            if pts.len() > 1 && pts.first() == pts.last() {
                pts.pop();
            } else if !*closed {
                return Err("the path is not closed (end it with Z)".into());
            }
            Ok(std::mem::take(pts))
        }
        [] => Err("the path has no segment".into()),
        more => Err(format!("the path has {} outlines: one stone per element", more.len())),
    }
}

/// A scanner of SVG number lists and path data.
struct Scanner<'a> {
    s: &'a [u8],
    i: usize,
}

impl<'a> Scanner<'a> {
    fn new(s: &'a str) -> Self {
        Self { s: s.as_bytes(), i: 0 }
    }

    fn skip(&mut self) {
        while self.i < self.s.len() && (self.s[self.i].is_ascii_whitespace() || self.s[self.i] == b',') {
            self.i += 1;
        }
    }

    fn at_end(&mut self) -> bool {
        self.skip();
        self.i >= self.s.len()
    }

    /// The next command letter, if the next token is one.
    fn command(&mut self) -> Option<char> {
        self.skip();
        let c = *self.s.get(self.i)?;
        (c.is_ascii_alphabetic() && c != b'e' && c != b'E').then(|| {
            self.i += 1;
            c as char
        })
    }

    /// The next number, None at the end or before a letter.
    fn number(&mut self) -> Result<Option<f64>, String> {
        self.skip();
        let start = self.i;
        let digits = |sc: &mut Self| {
            let b = sc.i;
            while sc.i < sc.s.len() && sc.s[sc.i].is_ascii_digit() {
                sc.i += 1;
            }
            sc.i > b
        };
        if self.i < self.s.len() && matches!(self.s[self.i], b'+' | b'-') {
            self.i += 1;
        }
        let int = digits(self);
        let frac = self.i < self.s.len() && self.s[self.i] == b'.' && {
            self.i += 1;
            digits(self)
        };
        if !int && !frac {
            self.i = start;
            return match self.s.get(start) {
                None => Ok(None),
                Some(c) if c.is_ascii_alphabetic() => Ok(None),
                Some(&c) => Err(format!("unexpected {:?} at character {}", c as char, start + 1)),
            };
        }
        if self.i < self.s.len() && matches!(self.s[self.i], b'e' | b'E') {
            let save = self.i;
            self.i += 1;
            if self.i < self.s.len() && matches!(self.s[self.i], b'+' | b'-') {
                self.i += 1;
            }
            if !digits(self) {
                self.i = save;
            }
        }
        let text = std::str::from_utf8(&self.s[start..self.i]).unwrap_or("");
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Some(v)),
            _ => Err(format!("{text:?} is not a finite number")),
        }
    }

    fn required(&mut self) -> Result<f64, String> {
        self.number()?.ok_or_else(|| format!("a number expected at character {}", self.i + 1))
    }

    fn pair(&mut self) -> Result<[f64; 2], String> {
        Ok([self.required()?, self.required()?])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_data_absolute_relative_and_implicit() {
        let p = path_outline("M0,0 h2 v1 L0 1z").unwrap();
        assert_eq!(p, vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]);
        let p = path_outline("m1-1 1 0 0 1-1 0Z").unwrap();
        assert_eq!(p, vec![[1.0, -1.0], [2.0, -1.0], [2.0, 0.0], [1.0, 0.0]]);
        assert!(path_outline("M0 0 C 1 1 2 2 3 3 Z").unwrap_err().contains("curve"));
        assert!(path_outline("M0 0 L1 0 L1 1").unwrap_err().contains("not closed"));
        assert!(path_outline("M0 0 L1 0 L1 1Z M5 5 L6 5 L6 6 Z").unwrap_err().contains("2 outlines"));
        assert_eq!(parse_points("1e-1,2.5.5 -3").unwrap(), vec![[0.1, 2.5], [0.5, -3.0]]);
    }

    #[test]
    fn transforms_compose_outermost_first() {
        let t = parse_transform("translate(10 0) scale(2)").unwrap();
        assert_eq!(apply(&t, [1.0, 1.0]), [12.0, 2.0]);
        let r = parse_transform("rotate(90, 1, 1)").unwrap();
        let p = apply(&r, [2.0, 1.0]);
        assert!((p[0] - 1.0).abs() < 1e-15 && (p[1] - 2.0).abs() < 1e-15, "{p:?}");
        assert!(parse_transform("spin(3)").is_err());
        assert!(parse_transform("a)b(").is_err());
        assert!(parse_points("1e999 0").is_err());
    }
}
