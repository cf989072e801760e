//! Reads back the closed straight-edged paths of an SVG the tool wrote (`cam::svg::to_svg`), so tests
//! can compare what was drawn with what was meant. Not a general SVG parser: it knows the writer's own
//! attribute quoting and its absolute M, L, A, Z path commands.

use actuator_cam::Operation;

type Point = [f64; 2];

/// Why [`read_svg_polygons`] could not read a document.
#[derive(Debug, PartialEq)]
pub enum ParseError {
    UnterminatedElement(usize),
    MissingAttribute(usize, &'static str),
    UnknownColour(String),
    BadPathData(String, &'static str),
}

/// Value of attribute `name` inside one start tag (double-quoted, as we write it).
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

/// Ring of one `d` string if it is closed (ends in `Z`) and made of `M`/`L` only; paths with
/// arcs (circles, arcs) and open paths give `None`.
fn closed_ring(d: &str, height_mm: f64) -> Result<Option<Vec<Point>>, ParseError> {
    let bad = |why| ParseError::BadPathData(d.to_string(), why);
    let mut ring = Vec::new();
    let mut closed = false;
    let mut has_arc = false;
    // Commands are glued to their first number ("M1 2"); split them off.
    let spaced: String = d
        .chars()
        .flat_map(|c| match c {
            'M' | 'L' | 'A' | 'Z' => [' ', c, ' '],
            _ => ['\0', c, '\0'],
        })
        .filter(|&c| c != '\0')
        .collect();
    let mut tokens = spaced.split_whitespace();
    while let Some(cmd) = tokens.next() {
        if closed {
            return Err(bad("content after Z"));
        }
        let mut number = || -> Result<f64, ParseError> {
            tokens
                .next()
                .ok_or_else(|| bad("missing number"))?
                .parse::<f64>()
                .map_err(|_| bad("not a number"))
        };
        match cmd {
            "M" | "L" => {
                if (cmd == "M") != ring.is_empty() {
                    return Err(bad("M must start the path and appear once"));
                }
                let x = number()?;
                let y = number()?;
                ring.push([x, height_mm - y]);
            }
            "A" => {
                for _ in 0..7 {
                    number()?;
                }
                has_arc = true;
            }
            "Z" => closed = true,
            _ => return Err(bad("unsupported command (only absolute M, L, A, Z)")),
        }
    }
    Ok((closed && !has_arc).then_some(ring))
}

/// Reads back the closed straight-edged paths of an SVG written by `to_svg`: each as its
/// operation (from the stroke colour) and its ring in drawing coordinates (y up), in document
/// order. Open paths and paths with arcs (circles, arcs) are skipped.
pub fn read_svg_polygons(svg_text: &str) -> Result<Vec<(Operation, Vec<Point>)>, ParseError> {
    let root = svg_text.find("<svg").unwrap_or(0);
    let height_mm = svg_text[root..]
        .find('>')
        .and_then(|end| attribute(&svg_text[root..root + end], "viewBox"))
        .and_then(|vb| vb.split_whitespace().nth(3))
        .and_then(|h| h.parse::<f64>().ok())
        .ok_or(ParseError::MissingAttribute(root, "viewBox"))?;
    let mut polygons = Vec::new();
    let mut pos = 0;
    while let Some(found) = svg_text[pos..].find("<path") {
        let start = pos + found;
        let len = svg_text[start..]
            .find('>')
            .ok_or(ParseError::UnterminatedElement(start))?;
        let tag = &svg_text[start..start + len];
        pos = start + len;
        let d = attribute(tag, "d").ok_or(ParseError::MissingAttribute(start, "d"))?;
        let stroke =
            attribute(tag, "stroke").ok_or(ParseError::MissingAttribute(start, "stroke"))?;
        let op = Operation::from_svg_colour(stroke)
            .ok_or_else(|| ParseError::UnknownColour(stroke.to_string()))?;
        if let Some(ring) = closed_ring(d, height_mm)? {
            polygons.push((op, ring));
        }
    }
    Ok(polygons)
}

/// The four numbers of an SVG's `viewBox`: x, y, width, height (mm).
pub fn view_box(svg: &str) -> Vec<f64> {
    svg.split("viewBox=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap()
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

/// Paths of one Inkscape layer of an SVG, as point lists, plus whether each is closed. A tiny reader
/// independent of the writer: it understands the M/L/Z subset the writer uses for polygons and lines.
pub fn svg_paths(svg: &str, layer: &str) -> Vec<(Vec<[f64; 2]>, bool)> {
    let height = view_box(svg)[3];
    let Some(group) = svg.split(&format!("inkscape:label=\"{layer}\"")).nth(1) else {
        return vec![];
    };
    let group = group.split("</g>").next().unwrap();
    group
        .split(" d=\"")
        .skip(1)
        .filter_map(|rest| {
            let d = rest.split('"').next().unwrap();
            if d.contains('A') {
                return None; // circles (holes) are not part outlines
            }
            let closed = d.trim_end().ends_with('Z');
            let nums: Vec<f64> = d
                .replace(['M', 'L', 'Z', ','], " ")
                .split_whitespace()
                .map(|t| t.parse().unwrap())
                .collect();
            Some((
                nums.chunks(2).map(|c| [c[0], height - c[1]]).collect(),
                closed,
            ))
        })
        .collect()
}
