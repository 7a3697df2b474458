//! The files of every crate import one way: no import circle between them.
//!
//! Each file of `src/` is a node. A file depends on the file that *defines* each item it names:
//! through a `use` of a `crate::`, `super::` or `self::` path or of a child module, through such
//! a path in its code, or by the bare name of an item its own `pub use` re-exports. A `pub use`
//! is a facade, not a dependency of the file that writes it: `tree/mod.rs` re-exporting
//! `tree::edge::Edge` does not depend on `edge.rs` unless its own code uses `Edge`. Files that
//! only tests compile (declared under `#[cfg(test)]`) and inline `mod tests` blocks are left
//! out. A circle is a strongly connected set of files; the test names them with their edges.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Source text with comments and the contents of string and character literals removed.
fn code_only(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            i += 2;
            while i + 1 < b.len() && !(b[i] == '*' && b[i + 1] == '/') {
                i += 1;
            }
            i += 2;
        } else if c == 'r'
            && (next == Some('"') || next == Some('#'))
            && (i == 0 || !(b[i - 1].is_alphanumeric() || b[i - 1] == '_'))
        {
            // A raw string r"..." or r#"..."#.
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (0..hashes).all(|h| b.get(j + 1 + h) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j;
        } else if c == '"' {
            i += 1;
            while i < b.len() && b[i] != '"' {
                i += if b[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' && (b.get(i + 2) == Some(&'\'') || next == Some('\\')) {
            // A character literal ('x', '\n', '\u{..}'); a lifetime has no closing quote.
            i += 1;
            while i < b.len() && b[i] != '\'' {
                i += if b[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("' '");
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The paths a `use` tree names, `as` renames dropped: `a::{b, c::{d, e}}` gives `a::b`,
/// `a::c::d`, `a::c::e`.
fn expand(tree: &str) -> Vec<Vec<String>> {
    let t: String = tree.split_whitespace().collect::<Vec<_>>().join(" ");
    fn rec(prefix: &str, s: &str, out: &mut Vec<Vec<String>>) {
        let s = s.trim();
        let s = s.split(" as ").next().unwrap().trim();
        if let Some(open) = s.find('{') {
            let base = format!("{prefix}{}", &s[..open]);
            let inner = &s[open + 1..s.rfind('}').unwrap_or(s.len())];
            let (mut depth, mut start) = (0, 0);
            for (k, ch) in inner.char_indices() {
                match ch {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        rec(&base, &inner[start..k], out);
                        start = k + 1;
                    }
                    _ => {}
                }
            }
            rec(&base, &inner[start..], out);
        } else if !s.is_empty() {
            let path = format!("{prefix}{s}");
            let segs: Vec<String> = path
                .split("::")
                .map(|x| x.trim().to_string())
                .filter(|x| !x.is_empty())
                .collect();
            if !segs.is_empty() {
                out.push(segs);
            }
        }
    }
    let mut out = Vec::new();
    rec("", &t, &mut out);
    out
}

/// One file: its module path, its child modules, what it uses, and what it re-exports.
#[derive(Default)]
struct File {
    uses: Vec<Vec<String>>,
    reexports: BTreeMap<String, Vec<String>>,
}

/// The module path (`a::b`) of the file at `rel` (`a/b.rs`, `a/b/mod.rs`; `lib.rs` is ``).
fn module_of(rel: &str) -> String {
    let mut parts: Vec<&str> = rel.trim_end_matches(".rs").split('/').collect();
    if matches!(parts.last(), Some(&"mod") | Some(&"lib") | Some(&"main")) {
        parts.pop();
    }
    parts.join("::")
}

/// The `use` statements of `code` as (public, use tree), and `code` without them and without
/// `mod x;` declarations.
fn split_uses(code: &str) -> (Vec<(bool, String)>, String) {
    let mut uses = Vec::new();
    let mut rest = String::new();
    let mut i = 0;
    let bytes = code.as_bytes();
    while i < code.len() {
        let at_word = i == 0 || !is_ident(code[..i].chars().next_back().unwrap());
        if at_word && code[i..].starts_with("use ") {
            let end = code[i..].find(';').map_or(code.len(), |e| i + e);
            let before = rest.trim_end();
            let public = before.ends_with("pub")
                || before.ends_with(')') && {
                    let open = before.rfind("pub(").unwrap_or(usize::MAX);
                    open != usize::MAX && !before[open..].contains('\n')
                };
            if public {
                let cut = before.rfind("pub").unwrap();
                rest.truncate(cut);
            }
            uses.push((public, code[i + 4..end].to_string()));
            i = end + 1;
        } else if at_word && code[i..].starts_with("mod ") {
            let end = code[i..].find([';', '{']).map_or(code.len(), |e| i + e);
            if bytes.get(end) == Some(&b';') {
                i = end + 1;
            } else {
                rest.push_str(&code[i..end]);
                i = end;
            }
        } else {
            let ch = code[i..].chars().next().unwrap();
            rest.push(ch);
            i += ch.len_utf8();
        }
    }
    (uses, rest)
}

/// The children a file declares (`mod x;`), with whether they are for tests only.
fn children(text: &str) -> Vec<(String, bool, Option<String>)> {
    let mut out = Vec::new();
    let (mut test, mut path) = (false, None);
    for line in text.lines().map(str::trim) {
        if line.starts_with("#[") {
            test |= line.starts_with("#[cfg(test)]");
            if let Some(p) = line.strip_prefix("#[path = \"") {
                path = p.split('"').next().map(str::to_string);
            }
            continue;
        }
        let decl = line
            .trim_start_matches("pub(crate) ")
            .trim_start_matches("pub(super) ")
            .trim_start_matches("pub ");
        if let Some(name) = decl.strip_prefix("mod ").and_then(|r| r.strip_suffix(';')) {
            out.push((name.trim().to_string(), test, path.take()));
        }
        test = false;
        path = None;
    }
    out
}

/// The files' import circles (each as its files, sorted), given every file as (path relative
/// to `src`, text).
fn circles(sources: &[(String, String)]) -> Vec<Vec<(String, Vec<String>)>> {
    // Files only tests compile.
    let mut test_only = BTreeSet::new();
    for (rel, text) in sources {
        let dir = match rel.rsplit_once('/') {
            Some((d, "mod.rs")) => d.to_string(),
            Some((d, f)) => format!("{d}/{}", f.trim_end_matches(".rs")),
            None if rel == "lib.rs" || rel == "main.rs" => String::new(),
            None => rel.trim_end_matches(".rs").to_string(),
        };
        let own_dir = rel.rsplit_once('/').map_or("", |(d, _)| d).to_string();
        for (name, test, path) in children(text) {
            if !test {
                continue;
            }
            let join = |d: &str, f: &str| {
                if d.is_empty() {
                    f.to_string()
                } else {
                    format!("{d}/{f}")
                }
            };
            match path {
                Some(p) => test_only.insert(join(&own_dir, &p)),
                None => {
                    test_only.insert(join(&dir, &format!("{name}.rs")));
                    test_only.insert(join(&dir, &format!("{name}/mod.rs")))
                }
            };
        }
    }
    let mut files: BTreeMap<String, File> = BTreeMap::new();
    let mut code_of: BTreeMap<String, (String, BTreeSet<String>)> = BTreeMap::new();
    for (rel, text) in sources.iter().filter(|(r, _)| !test_only.contains(r)) {
        let m = module_of(rel);
        let kids: BTreeSet<String> = children(text)
            .into_iter()
            .filter(|(_, test, _)| !test)
            .map(|(n, _, _)| n)
            .collect();
        let mut code = code_only(text);
        if let Some(k) = code.find("#[cfg(test)]\nmod tests {") {
            code.truncate(k);
        }
        let (uses, rest) = split_uses(&code);
        let mut f = File::default();
        for (public, tree) in uses {
            for mut segs in expand(&tree) {
                if kids.contains(&segs[0]) {
                    segs.insert(0, "self".into());
                }
                if !matches!(segs[0].as_str(), "crate" | "super" | "self") {
                    continue;
                }
                if public {
                    let name = segs.last().unwrap().clone();
                    if name != "*" {
                        f.reexports.insert(name, segs);
                    }
                } else {
                    f.uses.push(segs);
                }
            }
        }
        files.insert(m.clone(), f);
        code_of.insert(m, (rest, kids));
    }
    // Paths and re-exported names in the code.
    for (m, (rest, kids)) in &code_of {
        let chars: Vec<char> = rest.chars().collect();
        let mut found = Vec::new();
        let mut i = 0;
        while i < chars.len() {
            if !is_ident(chars[i]) || (i > 0 && is_ident(chars[i - 1])) {
                i += 1;
                continue;
            }
            let after_colons = i >= 2 && chars[i - 1] == ':' && chars[i - 2] == ':';
            let mut j = i;
            let mut segs = Vec::new();
            loop {
                let start = j;
                while j < chars.len() && is_ident(chars[j]) {
                    j += 1;
                }
                segs.push(chars[start..j].iter().collect::<String>());
                if j + 2 < chars.len()
                    && chars[j] == ':'
                    && chars[j + 1] == ':'
                    && is_ident(chars[j + 2])
                {
                    j += 2;
                } else {
                    break;
                }
            }
            if !after_colons {
                let first = segs[0].as_str();
                if matches!(first, "crate" | "super" | "self") && segs.len() > 1 {
                    found.push(segs.clone());
                } else if kids.contains(first) && segs.len() > 1 {
                    let mut s = vec!["self".to_string()];
                    s.extend(segs.iter().cloned());
                    found.push(s);
                } else if let Some(path) = files[m].reexports.get(first) {
                    found.push(path.clone());
                }
            }
            i = j;
        }
        files.get_mut(m).unwrap().uses.extend(found);
    }
    let absolute = |cur: &str, segs: &[String]| -> Vec<String> {
        let mut base: Vec<String> = cur
            .split("::")
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        let mut k = 0;
        match segs[0].as_str() {
            "crate" => {
                base.clear();
                k = 1;
            }
            "self" => k = 1,
            _ => {
                while k < segs.len() && segs[k] == "super" {
                    base.pop();
                    k += 1;
                }
            }
        }
        base.extend(segs[k..].iter().cloned());
        base
    };
    // The file that defines what `full` names, following re-exports.
    fn target(
        full: &[String],
        files: &BTreeMap<String, File>,
        absolute: &dyn Fn(&str, &[String]) -> Vec<String>,
        depth: usize,
    ) -> Option<String> {
        for k in (0..=full.len()).rev() {
            let m = full[..k].join("::");
            if let Some(f) = files.get(&m) {
                if let Some(next) = full.get(k).and_then(|n| f.reexports.get(n)) {
                    if depth < 8 {
                        return target(&absolute(&m, next), files, absolute, depth + 1);
                    }
                }
                return Some(m);
            }
        }
        None
    }
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (m, f) in &files {
        let to = graph.entry(m.clone()).or_default();
        for segs in &f.uses {
            if let Some(t) = target(&absolute(m, segs), &files, &absolute, 0) {
                if &t != m {
                    to.insert(t);
                }
            }
        }
    }
    // Strongly connected components (Tarjan).
    struct Tarjan<'g> {
        graph: &'g BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'g str, usize>,
        low: BTreeMap<&'g str, usize>,
        stack: Vec<&'g str>,
        on: BTreeSet<&'g str>,
        out: Vec<Vec<&'g str>>,
    }
    impl<'g> Tarjan<'g> {
        fn visit(&mut self, v: &'g str) {
            let n = self.index.len();
            self.index.insert(v, n);
            self.low.insert(v, n);
            self.stack.push(v);
            self.on.insert(v);
            for w in self.graph.get(v).into_iter().flatten() {
                let w = w.as_str();
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let l = self.low[v].min(self.low[w]);
                    self.low.insert(v, l);
                } else if self.on.contains(w) {
                    let l = self.low[v].min(self.index[w]);
                    self.low.insert(v, l);
                }
            }
            if self.low[v] == self.index[v] {
                let mut comp = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on.remove(w);
                    comp.push(w);
                    if w == v {
                        break;
                    }
                }
                if comp.len() > 1 {
                    self.out.push(comp);
                }
            }
        }
    }
    let mut t = Tarjan {
        graph: &graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !t.index.contains_key(v.as_str()) {
            t.visit(v);
        }
    }
    t.out
        .into_iter()
        .map(|mut comp| {
            comp.sort();
            let set: BTreeSet<&str> = comp.iter().copied().collect();
            comp.iter()
                .map(|a| {
                    let to = graph[*a]
                        .iter()
                        .filter(|b| set.contains(b.as_str()))
                        .cloned()
                        .collect();
                    (a.to_string(), to)
                })
                .collect()
        })
        .collect()
}

fn sources_under(dir: &Path) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p
                    .strip_prefix(dir)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                out.push((rel, std::fs::read_to_string(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

fn files(list: &[(&str, &str)]) -> Vec<(String, String)> {
    list.iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect()
}

/// Every crate of the repository (the workspace's and the Python package's): no import circle
/// between the files of any.
#[test]
fn no_crate_has_an_import_circle() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut checked = Vec::new();
    for entry in std::fs::read_dir(&crates).unwrap() {
        let src = entry.unwrap().path().join("src");
        if !src.is_dir() {
            continue;
        }
        let sources = sources_under(&src);
        let found = circles(&sources);
        assert!(
            found.is_empty(),
            "import circles in {} (file -> the files of the circle it uses): {found:#?}",
            src.display()
        );
        checked.push((src, sources.len()));
    }
    // The library, the simulator, the plots, the command line and the Python package.
    assert!(checked.len() >= 5, "{checked:?}");
    assert!(checked.iter().any(|(_, n)| *n > 100), "{checked:?}");
}

#[test]
fn two_files_that_use_each_other_are_a_circle() {
    let found = circles(&files(&[
        ("lib.rs", "pub mod a;\npub mod b;\n"),
        ("a.rs", "use crate::b::B;\npub struct A(B);\n"),
        ("b.rs", "pub struct B;\nfn f() -> crate::a::A { todo!() }\n"),
    ]));
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(
        found[0].iter().map(|(f, _)| f.as_str()).collect::<Vec<_>>(),
        ["a", "b"]
    );
}

#[test]
fn a_re_export_is_a_facade_until_its_module_uses_it() {
    let facade = |parent_code: &str| {
        circles(&files(&[
            ("lib.rs", "pub mod tree;\n"),
            (
                "tree/mod.rs",
                &format!("mod edge;\npub use edge::Edge;\npub const GATE: f64 = 1.0;\n{parent_code}"),
            ),
            ("tree/edge.rs", "use super::GATE;\npub struct Edge(f64);\n// super::nothing\nconst S: &str = \"crate::tree::edge\";\n"),
        ]))
    };
    assert!(facade("").is_empty(), "{:?}", facade(""));
    assert_eq!(facade("pub struct Tree { edges: Vec<Edge> }\n").len(), 1);
    assert_eq!(facade("fn f() { edge::helper() }\n").len(), 1);
}

#[test]
fn what_only_tests_compile_is_left_out() {
    let b = |tests: &str| {
        circles(&files(&[
            ("lib.rs", "pub mod a;\npub mod b;\n"),
            ("a.rs", "use crate::b::B;\npub struct A(B);\n"),
            ("b.rs", &format!("pub struct B;\n{tests}")),
        ]))
    };
    assert!(b("#[cfg(test)]\nmod tests {\n    use crate::a::A;\n}\n").is_empty());
    assert_eq!(b("fn f(_: crate::a::A) {}\n").len(), 1);
}
