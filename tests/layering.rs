//! Module layering of flank: no import circle between files, no upward
//! import between top-level modules.
//!
//! The test reads `src/` with `syn` (not the compiler) and builds a graph of
//! files: `a.rs -> b.rs` when the non-test code of `a.rs` names an item (fn,
//! struct, enum, union, trait, type, const, static, macro) *defined* in
//! `b.rs`, through a private `use` or a path in code (`crate::…`, `super::…`,
//! `self::…`, a module declared or imported in the file, `flank::…` in the
//! binary). Re-exports (`pub use`, `pub(crate) use`, …) are no edges: a name
//! reached through one counts for the file that defines it; a variant or an
//! associated item counts for the file of its type. Code under
//! `#[cfg(test)]`, `#[test]` functions and modules reached only through a
//! `#[cfg(test)] mod` are left out; `#[cfg(feature = …)]` code counts.
//!
//! Why: each module does one job and sits on the modules below it; lower
//! layers never import higher ones. A file that needs a higher layer, or two
//! files that need each other, are where jobs got mixed (often a type that
//! belongs lower down, e.g. a settings enum kept beside the solver reading it).
//!
//! * **Circle**: files that reach each other through their imports (a
//!   strongly connected component of more than one file). The failure lists
//!   each circle, then one line per edge inside it, `a.rs -> b.rs: Name1,
//!   Name2`: the names `a.rs` takes from `b.rs`. Break it by moving those
//!   names to a file both can import, or by passing them in.
//! * **Upward import**: an edge from a file of top-level module A to a file
//!   of another top-level module B whose layer in [`LAYERS`] is not below
//!   A's (equal layers may not import each other at all). The binary
//!   (`src/main.rs`, `src/cli/`) is above every layer; `lib.rs` is in none.
//!   A top-level module missing from [`LAYERS`] fails too: give it a layer.
//!
//! Paths into the crate that the resolver cannot follow are printed as
//! warnings (`cargo test --test layering -- --nocapture`); they do not fail.
//! `FLANK_SRC=dir` checks another source tree.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use syn::buffer::{Cursor, TokenBuffer};
use syn::punctuated::Punctuated;
use syn::visit::{self, Visit};
use syn::{Attribute, ForeignItem, ImplItem, Item, Meta, UseTree, Visibility};

/// Top-level lib modules and their layers, lowest first. A module may import
/// only from modules of a lower number; names absent from `src/` are tolerated.
const LAYERS: &[(&str, u32)] = &[
    ("error", 0),     // the error type, imported by nearly everything
    ("text_file", 1), // leaves: text files, whole-file writes, SIGINT, memory guard, limits, GCI
    ("atomic_file", 1),
    ("interrupt", 1),
    ("progress", 1), // progress of long runs to an embedding program
    ("resources", 1),
    ("iteration_limits", 1),
    ("grid_convergence", 1),
    ("summary", 1),  // what every summary.json shares (schema version)
    ("settings", 2), // solver-settings enums shared by the scene and the solvers
    ("geometry", 3), // what a gear is: the gear-pair interface, flanks, micro-geometry
    ("fem", 4),      // elements, assembly, constraints, sparse Cholesky, static analysis
    ("mesh", 5),     // meshes, meshers, .msh import; CalculiX decks (deck)
    ("deck", 5),
    ("lubrication", 6), // lubricant data, EHL film and traction (scene files read lubricants)
    ("scene", 7),       // scene files (TOML) into gears, materials, loads, analysis options
    ("tca", 8),         // unloaded TCA, CalculiX runs, when a tooth pair counts as loaded
    ("ccx", 8),
    ("load_sharing", 8),
    ("contact", 9),     // node-to-surface FE contact
    ("report", 10),     // VTU, CSV, JSON output and plots (reads contact solutions)
    ("compliance", 11), // nodal compliance tensors, cache, interpolation
    ("ltca", 12),       // compliance-matrix LTCA
    ("mesh_cycle", 13), // FE contact over a mesh cycle (`flank run`)
    ("compare", 14),    // LTCA against FE contact (`flank compare`)
    ("campaign", 15),   // studies over many variants of a scene
    ("api", 16),        // the library's short API over the analyses
];

/// A name bound in a module: an item defined in a file, a submodule, or an
/// import (its path, resolved in the importing module).
enum Binding {
    Item(usize),
    Module(usize),
    Use(Vec<String>),
}

/// Where a path ends: an item (defining file, name) or a module.
#[derive(Clone)]
enum Target {
    Item(usize, String),
    Module(usize),
}

impl Target {
    fn module(&self) -> Option<usize> {
        if let Target::Module(m) = self {
            return Some(*m);
        }
        None
    }
}

/// A resolution: Ok(None) when the first name is not bound here (a local,
/// a generic, the prelude, another crate), Ok(Some([])) when it leads out of
/// the crate, Err when a name inside the crate is missing.
type Res = Result<Option<Vec<Target>>, String>;

type Edges = BTreeMap<(usize, usize), BTreeSet<String>>;

#[derive(Default)]
struct Module {
    name: String,
    file: usize,
    parent: Option<usize>,
    root: usize,
    top: Option<String>,
    bin: bool,
    inline: bool,
    child_dir: PathBuf,
    names: HashMap<String, Vec<Binding>>,
    globs: Vec<(Vec<String>, bool)>,
    uses: Vec<Vec<String>>,
    paths: BTreeSet<Vec<String>>,
}

#[derive(Default)]
struct Tree {
    src: PathBuf,
    files: Vec<PathBuf>,
    mods: Vec<Module>,
    lib: Option<usize>,
    bin: bool,
}

/// What the checker found: circles (one entry per circle, one line per
/// edge), upward imports, warnings, and the file graph.
struct Report {
    circles: Vec<String>,
    upward: Vec<String>,
    warnings: Vec<String>,
    edges: BTreeMap<(String, String), BTreeSet<String>>,
}

/// Some(false) when the cfg predicate is false in every non-test build
/// (features and platforms are unknown: None).
fn cfg_value(m: &Meta) -> Option<bool> {
    let Meta::List(l) = m else {
        return m.path().is_ident("test").then_some(false);
    };
    let args = Punctuated::<Meta, syn::Token![,]>::parse_terminated;
    let list = l.parse_args_with(args).ok()?;
    let v: Vec<Option<bool>> = list.iter().map(cfg_value).collect();
    let op = l.path.get_ident()?.to_string();
    match op.as_str() {
        "not" => v.first().copied().flatten().map(|b| !b),
        "all" if v.contains(&Some(false)) => Some(false),
        "any" if v.contains(&Some(true)) => Some(true),
        "all" | "any" => {
            let each = op == "all";
            v.iter().all(|x| *x == Some(each)).then_some(each)
        }
        _ => None,
    }
}

/// `#[cfg(test)]` (or any cfg false without `test`), `#[test]`, `#[bench]`.
fn is_test(attrs: &[Attribute]) -> bool {
    attrs.iter().any(|a| {
        let (p, cfg) = (a.path(), || a.parse_args::<Meta>().ok());
        let last = p.segments.last().map(|s| s.ident.to_string());
        matches!(last.as_deref(), Some("test" | "bench"))
            || p.is_ident("cfg") && cfg().is_some_and(|m| cfg_value(&m) == Some(false))
    })
}

fn has_attr(attrs: &[Attribute], name: &str) -> bool {
    attrs.iter().any(|a| a.path().is_ident(name))
}

/// An item's attributes and the name it defines (None: impl, use, mod, …).
fn item_parts(item: &Item) -> (&[Attribute], Option<&syn::Ident>) {
    match item {
        Item::Const(i) => (&i.attrs, Some(&i.ident)),
        Item::Enum(i) => (&i.attrs, Some(&i.ident)),
        Item::ExternCrate(i) => (&i.attrs, None),
        Item::Fn(i) => (&i.attrs, Some(&i.sig.ident)),
        Item::ForeignMod(i) => (&i.attrs, None),
        Item::Impl(i) => (&i.attrs, None),
        Item::Macro(i) => (&i.attrs, i.ident.as_ref()),
        Item::Mod(i) => (&i.attrs, None),
        Item::Static(i) => (&i.attrs, Some(&i.ident)),
        Item::Struct(i) => (&i.attrs, Some(&i.ident)),
        Item::Trait(i) => (&i.attrs, Some(&i.ident)),
        Item::TraitAlias(i) => (&i.attrs, Some(&i.ident)),
        Item::Type(i) => (&i.attrs, Some(&i.ident)),
        Item::Union(i) => (&i.attrs, Some(&i.ident)),
        Item::Use(i) => (&i.attrs, None),
        _ => (&[], None),
    }
}

/// A `use` tree as (path, Some(bound name)) or (path, None) for a glob.
fn flatten(tree: &UseTree, prefix: &mut Vec<String>, out: &mut Vec<(Vec<String>, Option<String>)>) {
    let mut named = |ident: &syn::Ident, rename: Option<&syn::Ident>| {
        let mut path = prefix.clone();
        if ident != "self" {
            path.push(ident.to_string());
        }
        let alias = rename.map_or(path.last().cloned(), |r| Some(r.to_string()));
        out.push((path, alias));
    };
    match tree {
        UseTree::Name(n) => named(&n.ident, None),
        UseTree::Rename(r) => named(&r.ident, Some(&r.rename)),
        UseTree::Glob(_) => out.push((prefix.clone(), None)),
        UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            flatten(&p.tree, prefix, out);
            prefix.pop();
        }
        UseTree::Group(g) => g.items.iter().for_each(|t| flatten(t, prefix, out)),
    }
}

/// Paths named in code (types, expressions, patterns, bounds, impl headers,
/// macro names, `a::b` runs in macro tokens) and the `use` items of bodies.
/// Attributes (doc comments, derives), nested modules and test code are skipped.
#[derive(Default)]
struct Collector<'ast> {
    paths: BTreeSet<Vec<String>>,
    uses: Vec<&'ast syn::ItemUse>,
}

impl<'ast> Collector<'ast> {
    fn add(&mut self, path: Vec<String>) {
        if !path.is_empty() {
            self.paths.insert(path);
        }
    }

    fn qpath(&mut self, qself: Option<&'ast syn::QSelf>, path: &'ast syn::Path) {
        if let Some(q) = qself {
            self.visit_type(&q.ty);
            if q.position == 0 {
                // `<T>::f`: only T and the generic arguments name anything
                let args = path.segments.iter().map(|s| &s.arguments);
                return args.for_each(|a| self.visit_path_arguments(a));
            }
        }
        self.visit_path(path);
    }

    fn scan(&mut self, mut c: Cursor) {
        let mut cur = Vec::new();
        while !c.eof() {
            if let Some((ident, next)) = c.ident() {
                cur.push(ident.to_string());
                c = next;
                match colon(next).and_then(colon) {
                    Some(n) => c = n,
                    None => self.add(std::mem::take(&mut cur)),
                }
                continue;
            }
            self.add(std::mem::take(&mut cur));
            if let Some((inner, ..)) = c.any_group() {
                self.scan(inner);
            }
            match c.token_tree() {
                Some((_, next)) => c = next,
                None => break,
            }
        }
        self.add(cur);
    }
}

/// The cursor after a `:`, if `c` starts with one.
fn colon(c: Cursor) -> Option<Cursor> {
    let (p, next) = c.punct()?;
    (p.as_char() == ':').then_some(next)
}

impl<'ast> Visit<'ast> for Collector<'ast> {
    fn visit_item(&mut self, i: &'ast Item) {
        match i {
            _ if is_test(item_parts(i).0) => {}
            Item::Mod(_) => {}
            Item::Use(u) => self.uses.push(u),
            _ => visit::visit_item(self, i),
        }
    }
    fn visit_impl_item(&mut self, i: &'ast ImplItem) {
        let attrs = match i {
            ImplItem::Fn(f) => &f.attrs[..],
            ImplItem::Const(c) => &c.attrs,
            _ => &[],
        };
        if !is_test(attrs) {
            visit::visit_impl_item(self, i);
        }
    }
    fn visit_attribute(&mut self, _: &'ast Attribute) {}
    fn visit_path(&mut self, p: &'ast syn::Path) {
        let colon = p.leading_colon.map(|_| "::".to_string());
        let segs = p.segments.iter().map(|s| s.ident.to_string());
        self.add(colon.into_iter().chain(segs).collect());
        visit::visit_path(self, p);
    }
    fn visit_expr_path(&mut self, e: &'ast syn::ExprPath) {
        self.qpath(e.qself.as_ref(), &e.path);
    }
    fn visit_type_path(&mut self, t: &'ast syn::TypePath) {
        self.qpath(t.qself.as_ref(), &t.path);
    }
    fn visit_macro(&mut self, m: &'ast syn::Macro) {
        self.visit_path(&m.path);
        self.scan(TokenBuffer::new2(m.tokens.clone()).begin());
    }
}

impl Tree {
    fn rel(&self, file: usize) -> String {
        let p = &self.files[file];
        let rel = p.strip_prefix(&self.src).unwrap_or(p);
        let parts: Vec<_> = rel.iter().map(|c| c.to_string_lossy()).collect();
        parts.join("/")
    }

    fn parse(&mut self, path: &Path) -> Result<(usize, syn::File), String> {
        let err =
            |what, e: &dyn std::fmt::Display| format!("cannot {what} {}: {e}", path.display());
        let text = std::fs::read_to_string(path).map_err(|e| err("read", &e))?;
        let file = syn::parse_file(&text).map_err(|e| err("parse", &e))?;
        if let Some(id) = self.files.iter().position(|f| f == path) {
            return Ok((id, file));
        }
        self.files.push(path.to_path_buf());
        Ok((self.files.len() - 1, file))
    }

    fn bind(&mut self, md: usize, name: String, b: Binding) {
        self.mods[md].names.entry(name).or_default().push(b);
    }

    fn add_use(&mut self, md: usize, u: &syn::ItemUse, private: bool) {
        let mut flat = Vec::new();
        let mut prefix: Vec<String> = u.leading_colon.iter().map(|_| "::".into()).collect();
        flatten(&u.tree, &mut prefix, &mut flat);
        for (path, alias) in flat {
            match alias {
                None => self.mods[md].globs.push((path, private)),
                Some(alias) => {
                    if private {
                        self.mods[md].uses.push(path.clone());
                    }
                    if alias != "_" {
                        self.bind(md, alias, Binding::Use(path));
                    }
                }
            }
        }
    }

    /// The file of `mod name;` in module `md`, and the folder of its submodules.
    fn mod_file(&self, md: usize, m: &syn::ItemMod) -> Result<(PathBuf, PathBuf), String> {
        let (here, name) = (&self.mods[md], m.ident.to_string());
        let at = format!("{}: mod {name}", self.rel(here.file));
        let attr = m.attrs.iter().find(|a| a.path().is_ident("path"));
        let dir = &here.child_dir;
        let (file_rs, mod_rs) = (
            dir.join(format!("{name}.rs")),
            dir.join(&name).join("mod.rs"),
        );
        let mut tried = vec![file_rs, mod_rs];
        if let Some(a) = attr {
            let nv = a
                .meta
                .require_name_value()
                .map_err(|e| format!("{at}: {e}"));
            let syn::Expr::Lit(lit) = &nv?.value else {
                return Err(format!("{at}: #[path] is not a string"));
            };
            let syn::Lit::Str(s) = &lit.lit else {
                return Err(format!("{at}: #[path] is not a string"));
            };
            let file_dir = self.files[here.file].parent().unwrap_or(&self.src);
            tried = vec![if here.inline { dir } else { file_dir }.join(s.value())];
        }
        let Some(path) = tried.iter().find(|p| p.is_file()) else {
            let tried: Vec<_> = tried.iter().map(|p| p.display().to_string()).collect();
            return Err(format!("{at}: no file {}", tried.join(" or ")));
        };
        // the submodules of mod.rs (or of a #[path] file) sit beside it, of foo.rs in foo/
        let beside = attr.is_some() || path.ends_with("mod.rs");
        let parent = path.parent().unwrap_or(dir).to_path_buf();
        Ok((
            path.clone(),
            if beside {
                parent
            } else {
                path.with_extension("")
            },
        ))
    }

    /// Adds a module (a file's, or an inline one) and, recursively, its submodules.
    fn add_module(
        &mut self,
        parent: Option<usize>,
        name: &str,
        file: usize,
        child_dir: PathBuf,
        inline: bool,
        items: &[Item],
    ) -> Result<usize, String> {
        let (id, p, bin) = (self.mods.len(), parent.map(|p| &self.mods[p]), self.bin);
        let top = match p {
            Some(p) if p.parent.is_none() && !bin => Some(name.to_string()),
            _ => p.and_then(|p| p.top.clone()),
        };
        let full = p.map_or(name.to_string(), |p| format!("{}::{name}", p.name));
        let root = p.map_or(id, |p| p.root);
        let mut m = Module::default();
        (m.name, m.file, m.parent, m.root, m.top) = (full, file, parent, root, top);
        (m.bin, m.inline, m.child_dir) = (bin, inline, child_dir);
        self.mods.push(m);
        for item in items.iter().filter(|i| !is_test(item_parts(i).0)) {
            match item {
                Item::Mod(m) => {
                    let name = m.ident.to_string();
                    let child = match &m.content {
                        Some((_, content)) => {
                            let dir = self.mods[id].child_dir.join(&name);
                            self.add_module(Some(id), &name, file, dir, true, content)?
                        }
                        None => {
                            let (path, dir) = self.mod_file(id, m)?;
                            let (file, parsed) = self.parse(&path)?;
                            self.add_module(Some(id), &name, file, dir, false, &parsed.items)?
                        }
                    };
                    self.bind(id, name, Binding::Module(child));
                }
                Item::Use(u) => self.add_use(id, u, matches!(u.vis, Visibility::Inherited)),
                _ => self.add_item(id, item),
            }
        }
        Ok(id)
    }

    /// The names an item defines, and what its code names.
    fn add_item(&mut self, id: usize, item: &Item) {
        let (file, root) = (self.mods[id].file, self.mods[id].root);
        let (attrs, name) = item_parts(item);
        let mut names: Vec<&syn::Ident> = name.into_iter().collect();
        let foreign = match item {
            Item::ForeignMod(f) => &f.items[..],
            _ => &[],
        };
        for fi in foreign {
            match fi {
                ForeignItem::Fn(f) => names.push(&f.sig.ident),
                ForeignItem::Static(s) => names.push(&s.ident),
                ForeignItem::Type(t) => names.push(&t.ident),
                _ => {}
            }
        }
        let export = matches!(item, Item::Macro(_)) && has_attr(attrs, "macro_export");
        for n in names.iter().map(|n| n.to_string()).filter(|n| n != "_") {
            if export {
                self.bind(root, n.clone(), Binding::Item(file));
            }
            self.bind(id, n, Binding::Item(file));
        }
        let mut c = Collector::default();
        c.visit_item(item);
        c.uses.iter().for_each(|u| self.add_use(id, u, true));
        self.mods[id].paths.extend(c.paths);
    }

    /// What `name` means as a member of module `md` (`globs`: also through
    /// its glob imports).
    fn lookup(&self, md: usize, name: &str, depth: usize, globs: bool) -> Res {
        let bs = self.mods[md].names.get(name).map_or(&[][..], |b| &b[..]);
        let direct: Vec<Target> = (bs.iter())
            .filter_map(|b| match b {
                Binding::Item(f) => Some(Target::Item(*f, name.to_string())),
                Binding::Module(c) => Some(Target::Module(*c)),
                Binding::Use(_) => None,
            })
            .collect();
        let mut found = direct.clone();
        for b in bs {
            let Binding::Use(p) = b else { continue };
            // `use m::m;` beside `mod m;` starts at the module, not at itself
            let r = match p[0] == name {
                true => self.walk(direct.clone(), &p[1..], depth + 1)?,
                false => self.resolve(md, p, depth + 1, true)?,
            };
            found.extend(r.unwrap_or_default());
        }
        if bs.is_empty() && globs {
            let g = self.glob_lookup(md, name, depth);
            return Ok((!g.is_empty()).then_some(g));
        }
        Ok((!bs.is_empty()).then_some(found))
    }

    /// `name` through the glob imports of `md` (cycles of globs end at a depth).
    fn glob_lookup(&self, md: usize, name: &str, depth: usize) -> Vec<Target> {
        let mut found = Vec::new();
        for (g, _) in self.mods[md].globs.iter().filter(|_| depth < 24) {
            let ts = self.resolve(md, g, depth + 1, false).ok().flatten();
            for gm in ts.unwrap_or_default().iter().filter_map(Target::module) {
                let t = self.lookup(gm, name, depth + 1, true).ok().flatten();
                found.extend(t.unwrap_or_default());
            }
        }
        found
    }

    /// Where `path`, named in module `scope`, ends (`globs`: its first name
    /// may come through a glob import).
    fn resolve(&self, scope: usize, path: &[String], depth: usize, globs: bool) -> Res {
        let (m, Some(first)) = (&self.mods[scope], path.first()) else {
            return Ok(None);
        };
        if depth > 32 {
            return Err("re-export chain too deep".into());
        }
        let module = |md| vec![Target::Module(md)];
        let flank = self.lib.filter(|_| m.bin).map(module); // `flank::` in the binary
        let (start, n) = match first.as_str() {
            "crate" | "$crate" => (module(m.root), 1),
            "self" => (module(scope), 1),
            "super" => {
                let n = path.iter().take_while(|s| *s == "super").count();
                let mut s = scope;
                for _ in 0..n {
                    s = self.mods[s].parent.ok_or("`super` above the crate root")?;
                }
                (module(s), n)
            }
            "::" if path.get(1).is_some_and(|s| s == "flank") => (flank.unwrap_or_default(), 2),
            "::" => return Ok(Some(Vec::new())),
            _ => match self.lookup(scope, first, depth, globs)? {
                Some(t) => (t, 1),
                None if first == "flank" && flank.is_some() => (flank.unwrap_or_default(), 1),
                None => return Ok(None),
            },
        };
        self.walk(start, &path[n..], depth)
    }

    /// Follows `path` from `cur`; stops at the first item (the rest are
    /// variants, associated items, methods) or where it leaves the crate.
    fn walk(&self, mut cur: Vec<Target>, path: &[String], depth: usize) -> Res {
        for seg in path {
            let mods: Vec<usize> = cur.iter().filter_map(Target::module).collect();
            let Some(&first) = mods.first() else { break };
            let mut next = None;
            for &md in &mods {
                if let Some(t) = self.lookup(md, seg, depth + 1, true)? {
                    next.get_or_insert_with(Vec::new).extend(t);
                }
            }
            cur = next.ok_or_else(|| format!("no `{seg}` in `{}`", self.mods[first].name))?;
        }
        Ok(Some(cur))
    }

    /// File edges with the names that make them, and the warnings.
    fn edges(&self) -> (Edges, BTreeSet<String>) {
        let (mut edges, mut warnings) = (Edges::new(), BTreeSet::new());
        for (id, m) in self.mods.iter().enumerate() {
            let mut add = |f: usize, n: String| {
                if f != m.file {
                    edges.entry((m.file, f)).or_default().insert(n);
                }
            };
            for p in m.uses.iter().chain(&m.paths) {
                match self.resolve(id, p, 0, true) {
                    Ok(ts) => (ts.into_iter().flatten()).for_each(|t| {
                        if let Target::Item(f, n) = t {
                            add(f, n)
                        }
                    }),
                    Err(e) => {
                        let at = format!("{} ({})", self.rel(m.file), m.name);
                        warnings.insert(format!("{at}: `{}`: {e}", p.join("::")));
                    }
                }
            }
            // a private glob import: the names used through it (above), the
            // variants of an enum, or at least the file of its module
            for (g, _) in m.globs.iter().filter(|g| g.1) {
                let ts = self.resolve(id, g, 0, false).ok().flatten();
                for t in ts.unwrap_or_default() {
                    match t {
                        Target::Item(f, n) => add(f, n),
                        Target::Module(gm) => {
                            let through = |p: &&Vec<String>| {
                                let t = self.lookup(gm, &p[0], 0, true).ok().flatten();
                                !m.names.contains_key(&p[0]) && t.is_some_and(|t| !t.is_empty())
                            };
                            if !m.paths.iter().any(|p| through(&p)) {
                                add(self.mods[gm].file, "*".into());
                            }
                        }
                    }
                }
            }
        }
        (edges, warnings)
    }
}

/// Strongly connected components (Tarjan).
fn tarjan(adj: &[Vec<usize>]) -> Vec<Vec<usize>> {
    /// index and low-link per node (None: not visited), the stack, the SCCs
    struct St(Vec<Option<(usize, usize)>>, Vec<usize>, Vec<Vec<usize>>);
    fn go(s: &mut St, adj: &[Vec<usize>], v: usize, next: &mut usize) -> usize {
        let index = *next;
        let mut low = index;
        (s.0[v], *next) = (Some((index, index)), index + 1);
        s.1.push(v);
        for &w in &adj[v] {
            match s.0[w] {
                None => low = low.min(go(s, adj, w, next)),
                Some((iw, _)) if s.1.contains(&w) => low = low.min(iw),
                Some(_) => {}
            }
        }
        s.0[v] = Some((index, low));
        if low == index {
            let at = s.1.iter().rposition(|&w| w == v).unwrap_or(0);
            let scc = s.1.split_off(at);
            s.2.push(scc);
        }
        low
    }
    let (mut s, mut next) = (St(vec![None; adj.len()], Vec::new(), Vec::new()), 0);
    for v in 0..adj.len() {
        if s.0[v].is_none() {
            go(&mut s, adj, v, &mut next);
        }
    }
    s.2
}

/// Reads the tree under `src` (lib.rs and/or main.rs) and checks it against `layers`.
fn check(src: &Path, layers: &[(&str, u32)]) -> Result<Report, String> {
    let mut t = Tree {
        src: src.to_path_buf(),
        ..Tree::default()
    };
    for (root, bin) in [("lib.rs", false), ("main.rs", true)] {
        let path = src.join(root);
        if path.is_file() {
            t.bin = bin;
            let (file, parsed) = t.parse(&path)?;
            let id = t.add_module(None, "crate", file, src.into(), false, &parsed.items)?;
            t.lib = t.lib.or((!bin).then_some(id));
        }
    }
    if t.mods.is_empty() {
        return Err(format!("neither lib.rs nor main.rs in {}", src.display()));
    }
    let (edges, warnings) = t.edges();
    let names = |e: &BTreeSet<String>| e.iter().cloned().collect::<Vec<_>>().join(", ");
    let line = |(a, b): (usize, usize)| {
        format!("{} -> {}: {}", t.rel(a), t.rel(b), names(&edges[&(a, b)]))
    };
    let mut adj = vec![Vec::new(); t.files.len()];
    edges.keys().for_each(|&(a, b)| adj[a].push(b));
    let mut circles = Vec::new();
    for c in tarjan(&adj).into_iter().filter(|c| c.len() > 1) {
        let mut files: Vec<String> = c.iter().map(|&f| t.rel(f)).collect();
        let inner = edges.keys().filter(|(a, b)| c.contains(a) && c.contains(b));
        let mut lines: Vec<String> = inner.map(|&e| format!("  {}", line(e))).collect();
        files.sort();
        lines.sort();
        let head = format!("circle of {} files: {}", c.len(), files.join(", "));
        circles.push(format!("{head}\n{}", lines.join("\n")));
    }
    circles.sort();
    // the top-level lib module of each file (None: lib.rs, the binary)
    let mut top: Vec<Option<&str>> = vec![None; t.files.len()];
    for m in t.mods.iter().filter(|m| !m.inline && !m.bin) {
        top[m.file] = m.top.as_deref();
    }
    let layer = |m: &str| layers.iter().find(|(n, _)| *n == m).map(|(_, l)| *l);
    let lib_mods = t
        .mods
        .iter()
        .filter(|m| m.parent.is_some_and(|p| Some(p) == t.lib));
    let missing = lib_mods.filter_map(|m| m.top.as_deref().filter(|m| layer(m).is_none()));
    let mut upward: Vec<String> = missing
        .map(|m| format!("module {m} is not in LAYERS"))
        .collect();
    for &(a, b) in edges.keys() {
        let (Some(ta), Some(tb)) = (top[a], top[b]) else {
            continue;
        };
        if let (true, Some(la), Some(lb)) = (ta != tb, layer(ta), layer(tb)) {
            if lb >= la {
                let (da, db) = (format!("{ta} is layer {la}"), format!("{tb} is layer {lb}"));
                upward.push(format!("{} ({da}, {db})", line((a, b))));
            }
        }
    }
    let edges = edges
        .into_iter()
        .map(|((a, b), n)| ((t.rel(a), t.rel(b)), n));
    let (edges, warnings) = (edges.collect(), warnings.into_iter().collect());
    Ok(Report {
        circles,
        upward,
        warnings,
        edges,
    })
}

fn flank_report() -> &'static Report {
    static REPORT: OnceLock<Result<Report, String>> = OnceLock::new();
    let r = REPORT.get_or_init(|| {
        let default = concat!(env!("CARGO_MANIFEST_DIR"), "/src");
        let src = std::env::var_os("FLANK_SRC").map_or(PathBuf::from(default), PathBuf::from);
        let r = check(&src, LAYERS)?;
        let (e, w) = (r.edges.len(), r.warnings.len());
        eprintln!(
            "layering: {}: {e} file edges, {w} unresolved paths",
            src.display()
        );
        r.warnings
            .iter()
            .for_each(|w| eprintln!("layering warning: {w}"));
        Ok(r)
    });
    r.as_ref().unwrap_or_else(|e| panic!("layering: {e}"))
}

#[test]
fn no_import_circles() {
    let c = &flank_report().circles;
    let head = "import circle(s) between files (a.rs -> b.rs: the names a.rs takes from b.rs)";
    assert!(c.is_empty(), "{} {head}:\n{}", c.len(), c.join("\n"));
}

#[test]
fn no_upward_imports() {
    let u = &flank_report().upward;
    let head =
        "upward import(s): a module imports only from lower layers (LAYERS in tests/layering.rs)";
    assert!(u.is_empty(), "{} {head}:\n{}", u.len(), u.join("\n"));
}

/// Writes a synthetic source tree, checks it, removes it.
fn check_tree(name: &str, layers: &[(&str, u32)], files: &[(&str, &str)]) -> Report {
    let dir = std::env::temp_dir().join(format!("flank-layering-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for (path, text) in files {
        let p = dir.join(path);
        std::fs::create_dir_all(p.parent().unwrap_or(&dir)).expect("temp dir");
        std::fs::write(&p, text).expect("temp file");
    }
    let r = check(&dir, layers);
    let _ = std::fs::remove_dir_all(&dir);
    r.unwrap_or_else(|e| panic!("{e}"))
}

/// The names of edge a -> b, "" when there is none.
fn edge(r: &Report, a: &str, b: &str) -> String {
    let names = r
        .edges
        .get(&(a.to_string(), b.to_string()))
        .into_iter()
        .flatten();
    names.cloned().collect::<Vec<_>>().join(", ")
}

#[test]
fn checker_finds_a_two_file_circle() {
    let a = ("a.rs", "use crate::b::B; pub struct A(pub B);");
    let b = (
        "b.rs",
        "pub struct B; pub fn f() -> super::a::A { crate::a::A(B) }",
    );
    let r = check_tree(
        "circle",
        &[("a", 0), ("b", 0)],
        &[("lib.rs", "mod a; mod b;"), a, b],
    );
    let circle = "circle of 2 files: a.rs, b.rs\n  a.rs -> b.rs: B\n  b.rs -> a.rs: A";
    assert_eq!(r.circles, [circle]);
}

#[test]
fn checker_follows_re_exports_without_circle() {
    let files = [
        ("lib.rs", "pub mod a; mod b; pub use a::*;"),
        (
            "a/mod.rs",
            "mod x; mod y; pub use x::X; pub(crate) use y::{Kind, Y}; pub struct C;",
        ),
        ("a/x.rs", "use super::{Y, C}; pub struct X(pub Y, pub C);"),
        ("a/y.rs", "pub struct Y; pub enum Kind { One }"),
        (
            "b.rs",
            "use crate::a; fn f(_: crate::X) -> a::Kind { a::Kind::One }",
        ),
    ];
    let r = check_tree("reexport", &[("a", 0), ("b", 1)], &files);
    assert!(r.circles.is_empty(), "{:?}", r.circles);
    assert_eq!(
        (edge(&r, "a/x.rs", "a/y.rs"), edge(&r, "a/x.rs", "a/mod.rs")),
        ("Y".into(), "C".into())
    );
    assert_eq!(
        (edge(&r, "b.rs", "a/x.rs"), edge(&r, "b.rs", "a/y.rs")),
        ("X".into(), "Kind".into())
    );
    assert_eq!(edge(&r, "a/mod.rs", "a/x.rs"), "");
    assert!(
        r.upward.is_empty() && r.warnings.is_empty(),
        "{:?} {:?}",
        r.upward,
        r.warnings
    );
}

#[test]
fn checker_ignores_test_code() {
    let b = "pub struct B;\n#[cfg(test)] use crate::a::A;\n#[cfg(all(test, unix))] mod t;\n\
             #[test] fn t() { let _ = crate::a::A; }\n#[cfg(test)] mod tests { use super::A; }\n\
             /// Not a path: [`crate::a::A`].\npub fn kept() { crate::a::f() }";
    let files = [
        ("lib.rs", "mod a; mod b; #[cfg(test)] mod testing;"),
        (
            "a.rs",
            "use crate::b::B; pub struct A(B);\n#[cfg(not(test))] pub fn f() {}",
        ),
        ("b.rs", b),
    ];
    let r = check_tree("cfgtest", &[("a", 0), ("b", 0)], &files);
    assert_eq!(
        (edge(&r, "a.rs", "b.rs"), edge(&r, "b.rs", "a.rs")),
        ("B".into(), "f".into())
    );
}

#[test]
fn checker_finds_upward_imports() {
    let files = [
        (
            "lib.rs",
            "pub mod low; pub mod high; pub mod peer; pub mod extra;",
        ),
        (
            "low.rs",
            "use crate::high::Opt; pub fn f(o: Opt) -> bool { matches!(o, Opt::A) }",
        ),
        (
            "high/mod.rs",
            "mod opt; pub use opt::Opt; pub fn g() { crate::low::f(Opt::A); }",
        ),
        ("high/opt.rs", "pub enum Opt { A }"),
        ("peer.rs", "pub fn h() { crate::high::g() }"),
        ("extra.rs", ""),
        (
            "main.rs",
            "mod cli { pub fn run() { flank::peer::h(); } } fn main() { cli::run() }",
        ),
    ];
    let r = check_tree("upward", &[("low", 0), ("high", 1), ("peer", 1)], &files);
    let upward = [
        "module extra is not in LAYERS",
        "low.rs -> high/opt.rs: Opt (low is layer 0, high is layer 1)",
        "peer.rs -> high/mod.rs: g (peer is layer 1, high is layer 1)",
    ];
    assert_eq!(r.upward, upward);
    assert!(r.circles.is_empty(), "{:?}", r.circles);
    assert_eq!(edge(&r, "main.rs", "peer.rs"), "h");
}

#[test]
fn checker_resolves_aliases_macros_and_path_attributes() {
    let files = [
        ("lib.rs", "pub mod ltca; pub mod util;"),
        (
            "ltca.rs",
            "pub mod qp; use crate::ltca::qp as q; fn f() { q::solve(); crate::tol!(); }",
        ),
        (
            "ltca/qp.rs",
            "#[path = \"qp_impl.rs\"] mod imp; pub use imp::*;",
        ),
        ("ltca/qp_impl.rs", "pub fn solve() {}"),
        (
            "util.rs",
            "#[macro_export] macro_rules! tol { () => { 1e-9 } }\nfn g() { vec![crate::no::X]; }",
        ),
    ];
    let r = check_tree("resolver", &[("ltca", 1), ("util", 0)], &files);
    assert_eq!(edge(&r, "ltca.rs", "ltca/qp_impl.rs"), "solve");
    assert_eq!(edge(&r, "ltca.rs", "util.rs"), "tol");
    assert_eq!(
        r.warnings,
        ["util.rs (crate::util): `crate::no::X`: no `no` in `crate`"]
    );
}
