//! A tiny document model written out twice, as Markdown and as HTML, so
//! that the two reports can never say different things.

/// A block of the report.
#[derive(Clone, Debug, PartialEq)]
pub enum Block {
    Heading(u8, String),
    Paragraph(String),
    List(Vec<String>),
    Table(Table),
    /// An image (path relative to the report) with its caption.
    Image {
        src: String,
        alt: String,
        caption: String,
    },
    /// An SVG drawing: linked by its path (relative to the report) from
    /// Markdown, its markup written into the HTML page itself.
    Svg {
        src: String,
        alt: String,
        caption: String,
        markup: String,
    },
}

/// A table: header cells, rows of cells, and which columns are numbers
/// (right-aligned).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
    pub numeric: Vec<bool>,
}

impl Table {
    pub fn new(header: &[&str]) -> Table {
        Table {
            header: header.iter().map(|s| s.to_string()).collect(),
            rows: Vec::new(),
            numeric: header.iter().enumerate().map(|(i, _)| i > 0).collect(),
        }
    }

    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }
}

/// The document as GitHub-flavoured Markdown.
pub fn to_markdown(blocks: &[Block]) -> String {
    let mut out = String::new();
    for b in blocks {
        match b {
            Block::Heading(level, text) => {
                out.push_str(&"#".repeat(usize::from((*level).clamp(1, 6))));
                out.push(' ');
                out.push_str(text);
                out.push_str("\n\n");
            }
            Block::Paragraph(text) => {
                out.push_str(text);
                out.push_str("\n\n");
            }
            Block::List(items) => {
                for i in items {
                    out.push_str("- ");
                    out.push_str(i);
                    out.push('\n');
                }
                out.push('\n');
            }
            Block::Table(t) => markdown_table(&mut out, t),
            Block::Image { src, alt, caption }
            | Block::Svg {
                src, alt, caption, ..
            } => {
                out.push_str(&format!("![{alt}]({src})\n\n*{caption}*\n\n"));
            }
        }
    }
    out
}

fn markdown_table(out: &mut String, t: &Table) {
    let cell = |s: &String| s.replace('|', "\\|");
    out.push_str("| ");
    out.push_str(&t.header.iter().map(cell).collect::<Vec<_>>().join(" | "));
    out.push_str(" |\n|");
    for i in 0..t.header.len() {
        out.push_str(if t.numeric.get(i) == Some(&true) {
            "---:|"
        } else {
            "---|"
        });
    }
    out.push('\n');
    for r in &t.rows {
        out.push_str("| ");
        out.push_str(&r.iter().map(cell).collect::<Vec<_>>().join(" | "));
        out.push_str(" |\n");
    }
    out.push('\n');
}

/// The document as a self-contained HTML page (images by relative path).
pub fn to_html(title: &str, blocks: &[Block]) -> String {
    let mut out = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n",
        escape(title)
    );
    for b in blocks {
        match b {
            Block::Heading(level, text) => {
                let l = (*level).clamp(1, 6);
                out.push_str(&format!("<h{l}>{}</h{l}>\n", escape(text)));
            }
            Block::Paragraph(text) => out.push_str(&format!("<p>{}</p>\n", inline(text))),
            Block::List(items) => {
                out.push_str("<ul>\n");
                for i in items {
                    out.push_str(&format!("<li>{}</li>\n", inline(i)));
                }
                out.push_str("</ul>\n");
            }
            Block::Table(t) => html_table(&mut out, t),
            Block::Image { src, alt, caption } => out.push_str(&format!(
                "<figure><img src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
                escape(src),
                escape(alt),
                inline(caption)
            )),
            Block::Svg {
                alt,
                caption,
                markup,
                ..
            } => out.push_str(&format!(
                "<figure role=\"img\" aria-label=\"{}\">{}<figcaption>{}</figcaption></figure>\n",
                escape(alt),
                svg_element(markup),
                inline(caption)
            )),
        }
    }
    out.push_str("</body>\n</html>\n");
    out
}

const STYLE: &str = "body{font-family:sans-serif;max-width:72em;margin:2em auto;padding:0 1em;line-height:1.45;color:#222}\
table{border-collapse:collapse;margin:0.5em 0 1.5em}th,td{border:1px solid #ccc;padding:0.25em 0.6em}\
th{background:#f2f2f2}td.n{text-align:right;font-variant-numeric:tabular-nums}\
figure{margin:1em 0 2em}img,figure svg{max-width:100%;height:auto}figcaption{font-style:italic;margin-top:0.3em}code{background:#f4f4f4}";

fn html_table(out: &mut String, t: &Table) {
    out.push_str("<table>\n<tr>");
    for h in &t.header {
        out.push_str(&format!("<th>{}</th>", escape(h)));
    }
    out.push_str("</tr>\n");
    for r in &t.rows {
        out.push_str("<tr>");
        for (i, c) in r.iter().enumerate() {
            let class = if t.numeric.get(i) == Some(&true) {
                " class=\"n\""
            } else {
                ""
            };
            out.push_str(&format!("<td{class}>{}</td>", inline(c)));
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</table>\n");
}

/// The `<svg>` element of an SVG file, without an XML declaration or
/// doctype before it, which HTML does not allow inside a page.
fn svg_element(markup: &str) -> &str {
    markup
        .find("<svg")
        .map_or(markup, |i| &markup[i..])
        .trim_end()
}

/// Escapes text and turns Markdown's `code` spans into `<code>`.
fn inline(text: &str) -> String {
    let escaped = escape(text);
    let mut out = String::new();
    for (i, part) in escaped.split('`').enumerate() {
        if i % 2 == 1 {
            out.push_str("<code>");
            out.push_str(part);
            out.push_str("</code>");
        } else {
            out.push_str(part);
        }
    }
    out
}

pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Vec<Block> {
        let mut t = Table::new(&["setting", "rays"]);
        t.row(vec!["a|b".into(), "1,000".into()]);
        vec![
            Block::Heading(2, "Table 4.1".into()),
            Block::Paragraph("Use `--quick` & <see>.".into()),
            Block::List(vec!["one".into()]),
            Block::Table(t),
            Block::Image {
                src: "figures/fig-4.1.svg".into(),
                alt: "Figure 4.1".into(),
                caption: "c".into(),
            },
            Block::Svg {
                src: "plots/p.svg".into(),
                alt: "P".into(),
                caption: "d".into(),
                markup: "<?xml version=\"1.0\"?>\n<svg width=\"4\"><text>x</text></svg>\n".into(),
            },
        ]
    }

    #[test]
    fn markdown_has_tables_and_images() {
        let md = to_markdown(&sample());
        assert!(md.contains("## Table 4.1\n"));
        assert!(md.contains("| setting | rays |\n|---|---:|\n| a\\|b | 1,000 |"));
        assert!(md.contains("![Figure 4.1](figures/fig-4.1.svg)"));
        assert!(md.contains("- one\n"));
        assert!(md.contains("![P](plots/p.svg)\n\n*d*"));
    }

    #[test]
    fn html_is_escaped_and_inline_images_are_relative() {
        let html = to_html("R & D", &sample());
        assert!(html.contains("<title>R &amp; D</title>"));
        assert!(html.contains("<code>--quick</code> &amp; &lt;see&gt;."));
        assert!(html.contains("<img src=\"figures/fig-4.1.svg\""));
        assert!(html.contains("<td class=\"n\">1,000</td>"));
        assert!(html.trim_end().ends_with("</html>"));
        assert!(html.contains(
            "aria-label=\"P\"><svg width=\"4\"><text>x</text></svg><figcaption>d</figcaption>"
        ));
        assert!(!html.contains("<?xml"));
    }
}
