//! The replay page: an HTML file that draws a [`ReplayData`] on an SVG and plays it, with its
//! data inline and its player script and style either inline (a page on its own) or in the
//! shared files [`PLAYER_FILE`] and [`STYLE_FILE`] next to it (the pages of a results folder).
//! No network either way.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::json;

use super::data::ReplayData;
use crate::Error;
use crate::results::report::esc;

/// The player script ([`ReplayData`] in, SVG out).
pub const PLAYER: &str = include_str!("player.js");

/// The name of the shared player script, in the folder of the pages that load it.
pub const PLAYER_FILE: &str = "player.js";
/// The name of the shared style, in the folder of the pages that load it.
pub const STYLE_FILE: &str = "player.css";

/// Where a page's player script and style are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Player {
    /// Inside the page: it opens on its own.
    Inline,
    /// In [`PLAYER_FILE`] and [`STYLE_FILE`] next to the page ([`write_player`]).
    Shared,
}

/// The page's style.
pub const STYLE: &str = "body{font-family:'DejaVu Sans',Helvetica,Arial,sans-serif;margin:1em;color:#222}\
h1{font-size:1.2em;margin:.2em 0}main{display:flex;gap:1em;flex-wrap:wrap;align-items:flex-start}\
#view{flex:1 1 640px;max-width:1000px;border:1px solid #ddd;background:#fff}\
aside{flex:0 1 300px;font-size:.85em}.controls{display:flex;gap:.5em;align-items:center;margin:.5em 0;flex-wrap:wrap}\
#scrub{flex:1;min-width:200px}#time{font-variant-numeric:tabular-nums;min-width:9em}\
.obstacle{fill:#969696;stroke:#5a5a5a;stroke-width:.05}.walls{fill:none;stroke:#000;stroke-width:.25}\
.goal{fill:none;stroke-width:.08}.goalx{stroke-width:.08}.start{fill:none;stroke-width:.08}\
.tree{fill:none;stroke:#c8c8c8;stroke-width:.04}.plan{fill:none;stroke-width:.22;stroke-opacity:.5}\
.plan.old{stroke-dasharray:.4 .3;stroke-opacity:.35}.trail{fill:none;stroke:#000;stroke-width:.07}\
.agent{stroke:#000;stroke-width:.06}.obs{fill:none;stroke:#000;stroke-width:.06;stroke-dasharray:.12 .08}\
.field-b{fill:none;stroke:#7a1fa2;stroke-width:.16}.field-g{fill:none;stroke:#e65100;stroke-width:.16}\
.event path{fill:none;stroke-width:.15}.event.contact path,.event.wall path{stroke:#c00}\
.event.replan path{stroke:#1565c0;fill:#1565c0;fill-opacity:.3}.event.leg path{stroke:#2e7d32}\
dl{display:grid;grid-template-columns:max-content auto;gap:.1em .8em;margin:.5em 0}dt{color:#555}\
ul#events{max-height:16em;overflow:auto;padding-left:1.2em;margin:.3em 0}a.contact,a.wall{color:#c00}\
.key span{display:inline-block;margin-right:.8em}.note{color:#666}";

/// The page of `data`, with its player inside.
pub fn html(data: &ReplayData) -> String {
    html_with(data, Player::Inline)
}

/// The page of `data`, with its player where `player` says.
pub fn html_with(data: &ReplayData, player: Player) -> String {
    let colors: Vec<String> = crate::plot::palette::AGENTS
        .iter()
        .map(|c| format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2))
        .collect();
    let mut v = super::pack::page_json(data);
    v["colors"] = json!(colors);
    // the data sits in a script element: no "</" may end it early
    let text = serde_json::to_string(&v)
        .expect("json")
        .replace("</", "<\\/");
    let mut o = String::with_capacity(text.len() + PLAYER.len() + 4096);
    let style = match player {
        Player::Inline => format!("<style>{STYLE}</style>"),
        Player::Shared => format!("<link rel=\"stylesheet\" href=\"{STYLE_FILE}\">"),
    };
    let _ = write!(
        o,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>replay: {t}</title>{style}</head>\n<body>\n<h1>{t}</h1>\n",
        t = esc(&data.title)
    );
    o.push_str("<div class=\"controls\"><button id=\"play\" type=\"button\">Play</button><button id=\"step-back\" type=\"button\" title=\"previous frame (←)\">◀</button><button id=\"step-fwd\" type=\"button\" title=\"next frame (→)\">▶</button>\
<input id=\"scrub\" type=\"range\" min=\"0\" step=\"0.001\" value=\"0\" aria-label=\"time\"><span id=\"time\"></span>\
<label>speed <select id=\"speed\"><option>0.25</option><option>0.5</option><option selected>1</option><option>2</option><option>4</option><option>8</option></select></label>\
<label><input id=\"tree-toggle\" type=\"checkbox\"> planner's tree</label></div>\n");
    o.push_str("<main><svg id=\"view\" xmlns=\"http://www.w3.org/2000/svg\"></svg><aside>");
    let _ = write!(
        o,
        "<div id=\"frame-info\"></div><div id=\"field-info\"></div><dl>"
    );
    for (k, v) in &data.info {
        let _ = write!(o, "<dt>{}</dt><dd>{}</dd>", esc(k), esc(v));
    }
    let _ = writeln!(
        o,
        "</dl><p class=\"key\"><span>● {} position</span><span>◌ observed</span><span>— path so far</span><span>▬ plan</span><span style=\"color:#7a1fa2\">→ field B</span><span style=\"color:#e65100\">→ gradient</span><span style=\"color:#c00\">✕ contact</span><span style=\"color:#1565c0\">◆ replan</span></p>\
<h2 style=\"font-size:1em\">Events</h2><ul id=\"events\"></ul>\
<p class=\"note\">Lengths in BL (one agent diameter). Filled circles: {}; dashed: camera detections. Keys: space plays, ← → step. The URL holds the time (<code>#t=3.2</code>). Contacts are found in the positions shown (docs/replay.md).</p></aside></main>",
        if data.truth_known {
            "true"
        } else {
            "estimated"
        },
        match (data.kind, data.truth_known) {
            ("planned", _) => "positions along the plan",
            (_, true) => "true positions (simulation)",
            _ => "the rig's estimates",
        }
    );
    let script = match player {
        Player::Inline => format!("<script>{PLAYER}</script>"),
        Player::Shared => format!("<script src=\"{PLAYER_FILE}\"></script>"),
    };
    let _ = write!(
        o,
        "<script type=\"application/json\" id=\"replay-data\">{text}</script>\n{script}\n</body></html>\n"
    );
    o
}

/// Writes `text` to `path`, creating its folder.
fn write_file(path: &Path, text: &str) -> Result<(), Error> {
    let fail = |e: std::io::Error| Error::Failed(format!("{}: {e}", path.display()));
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(fail)?;
    }
    std::fs::write(path, text).map_err(fail)
}

/// Writes the page of `data` to `path` (creating its folder), with its player inside.
pub fn write(path: &Path, data: &ReplayData) -> Result<(), Error> {
    write_with(path, data, Player::Inline)
}

/// Writes the page of `data` to `path` (creating its folder), with its player where `player`
/// says.
pub fn write_with(path: &Path, data: &ReplayData, player: Player) -> Result<(), Error> {
    write_file(path, &html_with(data, player))
}

/// Writes the shared player script and style into `dir`, for the pages written there with
/// [`Player::Shared`].
pub fn write_player(dir: &Path) -> Result<(), Error> {
    write_file(&dir.join(PLAYER_FILE), PLAYER)?;
    write_file(&dir.join(STYLE_FILE), STYLE)
}

#[cfg(test)]
mod tests {
    use magbench_env::Scenario;

    use super::*;

    #[test]
    fn the_data_cannot_end_its_script_early() {
        let s = Scenario::load("open-field").unwrap();
        let d = ReplayData::planned(
            &s,
            "a </script><b>".into(),
            &[],
            &[],
            &magbench_env::PlanningModel::new(&s.physics),
        );
        let page = html(&d);
        assert_eq!(
            page.matches("</script>").count(),
            2,
            "the data's and the player's"
        );
        assert!(
            page.contains("a &lt;/script&gt;&lt;b&gt;"),
            "the title is escaped"
        );
        assert!(!page.contains("src=\"http") && !page.contains("href=\"http"));
    }

    #[test]
    fn a_shared_page_links_the_player_instead_of_holding_it() {
        let s = Scenario::load("open-field").unwrap();
        let d = ReplayData::planned(
            &s,
            "t".into(),
            &[],
            &[],
            &magbench_env::PlanningModel::new(&s.physics),
        );
        let (inline, shared) = (html(&d), html_with(&d, Player::Shared));
        assert!(inline.contains(PLAYER) && inline.contains(STYLE));
        assert!(!shared.contains(PLAYER) && !shared.contains(STYLE));
        assert!(shared.contains("<script src=\"player.js\"></script>"));
        assert!(shared.contains("<link rel=\"stylesheet\" href=\"player.css\">"));
        assert_eq!(
            inline.len() - shared.len(),
            PLAYER.len() + STYLE.len() + "<style></style><script></script>".len()
                - "<link rel=\"stylesheet\" href=\"player.css\"><script src=\"player.js\"></script>"
                    .len()
        );
    }
}
