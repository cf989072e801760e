//! User text in the Markdown reports. Names, materials, layer names, file names and drawing entities a
//! user wrote go into headings, tables and lists, where a `|` ends a table cell, `*` and `_` start
//! emphasis, `<` starts raw HTML (a drawing entity `<path id="a">` would vanish from the rendered
//! report) and a line break ends the row or the item. Every such text goes through [`text`] or
//! [`code`]; the reports' own wording does not.

/// Characters CommonMark gives a meaning inside a line; each may be escaped with a backslash
/// (CommonMark 0.31, §2.4 "Backslash escapes": any ASCII punctuation). `#` is left alone: it only
/// makes a heading at the start of a line, and user text never starts one (`actuator 3 #2` stays
/// as written).
const SPECIAL: &[char] = &['\\', '`', '*', '_', '[', ']', '<', '>', '|', '&', '~'];

/// `text` as literal inline Markdown: control characters become spaces (one line), every character
/// in [`SPECIAL`] is backslash-escaped.
pub fn text(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.push(' ');
        } else {
            if SPECIAL.contains(&c) {
                out.push('\\');
            }
            out.push(c);
        }
    }
    out
}

/// `text` as a code span, delimiters included: a run of backticks one longer than the longest inside
/// it, padded with a space when the text starts or ends with a backtick (CommonMark §6.1). Control
/// characters become spaces; `|` is escaped, since a table row splits on it even inside a code span
/// (GitHub-flavoured Markdown, §4.10 "Tables").
pub fn code(text: &str) -> String {
    let body: String = text
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect::<String>()
        .replace('|', "\\|");
    let mut longest = 0;
    let mut run = 0;
    for c in body.chars() {
        run = if c == '`' { run + 1 } else { 0 };
        longest = longest.max(run);
    }
    let fence = "`".repeat(longest + 1);
    let pad = if body.starts_with('`') || body.ends_with('`') {
        " "
    } else {
        ""
    };
    format!("{fence}{pad}{body}{pad}{fence}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_names_stay_as_they_are() {
        assert_eq!(text("thesis-C"), "thesis-C");
        assert_eq!(
            text("PZT sheet (Piezo Systems), 0.127 mm"),
            "PZT sheet (Piezo Systems), 0.127 mm"
        );
        assert_eq!(code("report.md"), "`report.md`");
    }

    #[test]
    fn markup_and_line_breaks_are_made_literal() {
        assert_eq!(text("a|b"), "a\\|b");
        assert_eq!(text("*bold* _x_"), "\\*bold\\* \\_x\\_");
        assert_eq!(text("<path id=\"w\">"), "\\<path id=\"w\"\\>");
        assert_eq!(text("two\nlines\r"), "two lines ");
        assert_eq!(text("panel #2"), "panel #2");
    }

    #[test]
    fn a_code_span_outlasts_the_backticks_inside_it() {
        assert_eq!(code("a`b"), "``a`b``");
        assert_eq!(code("`x`"), "`` `x` ``");
        assert_eq!(code("a|b"), "`a\\|b`");
        assert_eq!(code("a\nb"), "`a b`");
    }
}
