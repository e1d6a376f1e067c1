//! `report.html`: one self-contained page (no network, no external scripts) with the summary
//! table, every figure (PNG as data URIs) and an animation of the robot for each plan (canvas and
//! inline JavaScript, `page.js`).

use super::methods::methods_html;
use super::{Animation, DomainRow, MethodRow, SummaryRow, SweepSummary};

/// A figure of the page: its picture and, for a plan, its animation.
#[derive(Debug, Clone)]
pub struct FigureEmbed {
    /// File stem, e.g. `fig06`: the section's anchor.
    pub name: String,
    /// Heading.
    pub title: String,
    /// What the figure shows.
    pub description: String,
    /// The PNG bytes (`None` for a plan shown by its animation only).
    pub png: Option<Vec<u8>>,
    /// The robot's animation, for a plan.
    pub animation: Option<Animation>,
}

/// What the page shows.
#[derive(Debug, Clone, Copy)]
pub struct Page<'a> {
    /// One row per case.
    pub rows: &'a [SummaryRow],
    /// One row per domain map.
    pub domains: &'a [DomainRow],
    /// Fig. 16's summary.
    pub sweep: Option<&'a SweepSummary>,
    /// The three methods side by side (Fig. 17).
    pub methods: &'a [MethodRow],
    /// The 3-link arm (Fig. 18).
    pub arm3: Option<&'a super::Arm3Row>,
    /// The 3-link arm inside a velocity limit (Fig. 19).
    pub arm3_limited: Option<&'a super::Arm3Row>,
    /// The closed loop's Monte Carlo (Fig. 20).
    pub closed_loop: Option<&'a super::closed_loop::ClosedLoop>,
    /// The figures, in order.
    pub figures: &'a [FigureEmbed],
    /// Wall time of the whole computation \[s\].
    pub seconds: f64,
}

/// Escapes text for HTML.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// Standard base64 (RFC 4648, with padding).
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], chunk.get(1).copied().unwrap_or(0), chunk.get(2).copied().unwrap_or(0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(char::from(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// A table header cell: a word holding a symbol (`|τ1|,`, `≤`) never breaks inside, nor does a
/// unit in brackets (`[N m]`).
pub fn head_cell(text: &str) -> String {
    let mut joined = String::with_capacity(text.len());
    let mut depth = 0usize;
    for c in text.chars() {
        match c {
            '[' => depth += 1,
            ']' => depth = depth.saturating_sub(1),
            _ => {}
        }
        joined.push(if c == ' ' && depth > 0 { '\u{a0}' } else { c });
    }
    let words: Vec<String> = joined
        .split(' ')
        .map(|w| {
            if w.chars().any(|c| !c.is_ascii_alphanumeric() && !matches!(c, ',' | '.' | ':' | '(' | ')' | '-')) {
                format!("<span class=\"nb\">{}</span>", escape(w))
            } else {
                escape(w)
            }
        })
        .collect();
    format!("<th>{}</th>", words.join(" "))
}

fn cell(text: impl AsRef<str>) -> String {
    format!("<td>{}</td>", escape(text.as_ref()))
}

fn verdict(ok: bool) -> String {
    if ok { "<td class=\"yes\">yes</td>".into() } else { "<td class=\"no\">NO</td>".into() }
}

fn summary_table(rows: &[SummaryRow]) -> String {
    let heads = [
        "case",
        "method",
        "a, b [m]",
        "final error [rad]",
        "certified (≤ 1e-9)",
        "torque final error [rad]",
        "torque certified (≤ 1e-6)",
        "peak |u1|, |u2| [rad/s]",
        "u(0) [rad/s]",
        "peak |τ1|, |τ2| [N m]",
        "ECSA iterations",
        "plan [ms]",
        "torques [ms]",
        "verify [ms]",
        "torque cert. [ms]",
        "paper: plan / torques [s]",
    ];
    let mut s = String::from("<div class=\"scroll\"><table>\n<tr>");
    for h in heads {
        s += &head_cell(h);
    }
    s += "</tr>\n";
    let e = |x: Option<f64>| x.map_or("-".to_string(), |x| super::numbers::scientific(x, 2));
    let p = |x: Option<[f64; 2]>| x.map_or("-".to_string(), |x| format!("{:.4}, {:.4}", x[0], x[1]));
    for r in rows {
        let ms = |f: fn(&super::StageSeconds) -> f64| {
            r.seconds.as_ref().map_or("-".to_string(), |t| format!("{:.2}", f(t) * 1e3))
        };
        let case =
            format!("<td class=\"left\"><a href=\"#{0}\">{0}</a></td>", escape(r.figure.as_ref().unwrap_or(&r.id)));
        s += "<tr>";
        s += &case;
        s += &format!("<td class=\"left\">{} {}</td>", escape(&r.method.to_uppercase()), escape(&r.variant));
        s += &cell(format!("{}, {}", r.mount[0], r.mount[1]));
        s += &cell(e(r.final_error));
        s += &verdict(r.certified);
        s += &cell(e(r.torque_final_error));
        s += &verdict(r.torque_certified);
        s += &cell(p(r.max_abs_u));
        s += &cell(p(r.u_start));
        s += &cell(p(r.max_abs_torque));
        s += &cell(r.iterations.map_or("-".into(), |i| i.to_string()));
        s += &cell(ms(|t| t.plan));
        s += &cell(ms(|t| t.torques));
        s += &cell(ms(|t| t.verify));
        s += &cell(ms(|t| t.torque_verify));
        s += &cell(r.paper_seconds.map_or("-".into(), |t| format!("{} / {}", t.plan, t.torques)));
        s += "</tr>\n";
        if let Some(err) = &r.error {
            s += &format!(
                "<tr><td class=\"left no\" colspan=\"16\">{}: no plan: {}</td></tr>\n",
                escape(&r.id),
                escape(err)
            );
        }
    }
    s += "</table></div>\n";
    s
}

fn domain_table(domains: &[DomainRow]) -> String {
    let mut s = String::from(
        "<div class=\"scroll\"><table>\n<tr><th>figure</th><th>a, b [m]</th><th>components</th><th>start-component fraction</th>\
         <th>q0, qd connected</th><th class=\"left\">Eq. (14) plan q0 → qd</th></tr>\n",
    );
    for d in domains {
        s += &format!(
            "<tr><td class=\"left\"><a href=\"#{0}\">{0}</a></td>{1}{2}{3}{4}<td class=\"left\">{5}</td></tr>\n",
            escape(&d.figure),
            cell(format!("{}, {}", d.summary.mount[0], d.summary.mount[1])),
            cell(d.summary.components.to_string()),
            cell(format!("{:.2} %", 100.0 * d.summary.start_component_fraction)),
            verdict(d.summary.start_goal_connected),
            escape(&d.plan_text())
        );
    }
    s += "</table></div>\n";
    s
}

/// The page. Fails only if the animation data cannot be serialized.
pub fn page(p: &Page) -> Result<String, serde_json::Error> {
    let animations: Vec<&Animation> = p.figures.iter().filter_map(|f| f.animation.as_ref()).collect();
    // `</` inside a script element would end it early.
    let data = serde_json::to_string(&animations)?.replace("</", "<\\/");
    let mut s = String::from("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    s += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
    s += "<title>freefloat reproduce: normal form approach for a free-floating space robot</title>\n";
    s += &format!("<style>\n{}</style>\n</head>\n", include_str!("page.css"));
    s += "<body data-status=\"loading\" data-painted=\"0\">\n";
    s += "<p id=\"script-error\" hidden></p>\n";
    s += "<h1>freefloat reproduce: the paper's Sec. 5, and beyond</h1>\n";
    s += "<p>K. Tchoń, J. Ratajczak et al., <i>Normal form approach in the motion planning of space robots: a \
          case study</i>. The SRC space manipulator, q0 = (45, 120, 80) deg → qd = (0, 180, 140) deg in T = 10 s, \
          1001 samples. Every plan is verified by integrating the driftless system (7) with an adaptive integrator \
          (velocity level, tolerance 1e-9 rad), and its torques by integrating the full dynamics from rest \
          (torque level, tolerance 1e-6 rad).</p>\n";
    s += &format!(
        "<p class=\"note\">Computed in {:.2} s of wall time (all cases, maps, sweep and pictures). Times in the \
         table are this run's; the paper's (Sec. 6, i7-6700HQ) are beside them.</p>\n",
        p.seconds
    );
    s += "<p class=\"note\">This page needs no other file: its pictures are embedded. <code>freefloat \
          reproduce</code> also writes each figure as SVG and PNG (e.g. <code>fig06.svg</code>, \
          <code>fig06.png</code>) beside it.</p>\n";
    s += "<nav>";
    for f in p.figures {
        s += &format!("<a href=\"#{0}\">{0}</a>", escape(&f.name));
    }
    s += "</nav>\n<h2>Summary</h2>\n";
    s += &summary_table(p.rows);
    s += "<p class=\"note\">The ECSA's plain trigonometric series (Figs. 9-12) does not start at rest (u(0) ≠ 0): \
          the forward dynamics from rest cannot follow it, so its torque level is not certified; the \
          sin²-windowed ECSA starts and ends at rest. Fig. 15 is certified at the velocity level; its open-loop \
          torque plan (fast joint loops) is ill-conditioned and not certified at the torque level.</p>\n";
    s += "<h2>Domains of Eq. (14)</h2>\n";
    s += &domain_table(p.domains);
    if let Some(w) = p.sweep {
        s += &format!(
            "<p>Fig. 16: {} mounting points, a, b in [{}, {}] m, domain grid {}, {} random start/goal pairs per \
             point: mean best NFA success rate {:.1} %; the paper's q0 and qd are connected by Eq. (14) at {:.1} % \
             of the points ({:.2} s).</p>\n",
            w.points,
            w.a[0],
            w.a[1],
            w.grid,
            w.trials,
            100.0 * w.mean_rate,
            100.0 * w.connected_share,
            w.seconds
        );
    }
    if !p.methods.is_empty() {
        s += "<h2>Three methods (<a href=\"#fig17\">Fig. 17</a>)</h2>\n";
        s += "<p>The paper's problem by the minimum-effort planner, the NFA (auto: Eq. (12) or (14), else the \
              global normal form) and the ECSA (plain series), each with its default options. Peaks are the \
              motion's (refined between samples); effort is ∫|u|² dt.</p>\n";
        s += &methods_html(p.methods);
    }
    if let Some(row) = p.arm3 {
        s += "<h2>A 3-link arm (<a href=\"#fig18\">Fig. 18</a>)</h2>\n";
        s += &super::arm3::arm3_html(row);
        if let Some(limited) = p.arm3_limited {
            s += &super::arm3::arm3_limited_html(limited);
        }
    }
    if let Some(c) = p.closed_loop {
        s += "<h2>Closed loop (<a href=\"#fig20\">Fig. 20</a>)</h2>\n";
        s += &super::closed_loop::closed_loop_html(c);
    }
    s += "<h2>Figures</h2>\n";
    s += "<p class=\"note\">Animations: the base (grey rectangle, 0.6 m × 0.5 m, illustrative) at its \
          orientation φ around its centre of mass, the bar to the mounting point (a, b), link 1 (blue), link 2 \
          (green) and, for the 3-link arm, link 3 (pink), and the end-effector's path (orange: travelled). The system's centre of mass stays at the \
          origin (+): Eq. (4) with zero linear momentum. Each canvas has this legend and a scale bar.</p>\n";
    for f in p.figures {
        s += &format!("<section class=\"figure\" id=\"{}\">\n", escape(&f.name));
        s += &format!("<h3>{}</h3>\n<p>{}</p>\n", escape(&f.title), escape(&f.description));
        if let Some(png) = &f.png {
            s += &format!(
                "<img src=\"data:image/png;base64,{}\" alt=\"{}\">\n",
                base64(png),
                escape(&format!("{}: {}", f.name, f.title))
            );
        }
        if let Some(a) = &f.animation {
            s += &format!("<div class=\"anim\" data-case=\"{}\"></div>\n", escape(&a.id));
        }
        s += "</section>\n";
    }
    s += &format!("<script id=\"animations\" type=\"application/json\">{data}</script>\n");
    s += &format!("<script>\n{}</script>\n", include_str!("page.js"));
    s += "</body>\n</html>\n";
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        for (input, output) in
            [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foob", "Zm9vYg=="), ("foobar", "Zm9vYmFy")]
        {
            assert_eq!(base64(input.as_bytes()), output);
        }
    }

    /// Symbols in table headers do not break: `|τ1|,` is one unbreakable word.
    #[test]
    fn header_symbols_do_not_break() {
        let th = head_cell("peak |τ1|, |τ2| [N m]");
        let nb = |w: &str| format!("<span class=\"nb\">{w}</span>");
        assert_eq!(th, format!("<th>peak {} {} {}</th>", nb("|τ1|,"), nb("|τ2|"), nb("[N\u{a0}m]")));
        assert!(include_str!("page.css").contains(".nb { white-space: nowrap; }"));
    }

    /// The animation explains its marks: a legend (the "+" is the system's centre of mass, the
    /// grey bar goes from the base to the mounting point) and a scale bar in metres.
    #[test]
    fn animation_has_a_legend_and_a_scale_bar() {
        let js = include_str!("page.js");
        for text in ["centre of mass of the system (fixed)", "base to mounting point (a, b)", "barLength + \" m\""] {
            assert!(js.contains(text), "page.js lacks {text}");
        }
    }

    #[test]
    fn escape_escapes_markup() {
        assert_eq!(escape("a < b & \"c\""), "a &lt; b &amp; &quot;c&quot;");
    }
}
