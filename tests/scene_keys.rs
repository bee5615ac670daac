//! Every scene-file key is documented in `docs/scene.md`, and the document
//! lists no key that does not exist.
//!
//! The test reads `src/scene/*.rs` with `syn` (not the compiler) and
//! collects every struct that derives `Deserialize` (the `Raw*` structs and
//! the `[analyses.*]` option structs; code under `#[cfg(test)]` is left
//! out). Its keys are its fields' names after `#[serde(rename = …)]` and the
//! struct's `rename_all`, with their `alias`es; `skip`/`skip_deserializing`
//! fields are no keys, and a `#[serde(flatten)]` field is replaced by the
//! keys of the struct it flattens. (`Raw*` structs that do not derive
//! `Deserialize`, e.g. `RawMemberCutting`, are assembled in code and define
//! no key.)
//!
//! Which table a struct is read into is derived from the field types,
//! starting at the roots in [`MAPPED`]: a field `micro: Option<RawMicro>` of
//! the struct read at `[pinion]` puts `RawMicro` at `[pinion.micro]`
//! (through `Option`, `Spanned`, `Box` and `Vec`; a map `BTreeMap<String,
//! RawMaterial>` at `[materials]` puts `RawMaterial` at
//! `[materials.<name>]`). [`MAPPED`] also names the tables that cannot be
//! derived: the `[analyses.*]` structs (dispatched by name from a map of
//! TOML values) and the `[blank]` input set (read from a map of TOML values
//! by `BlankInputs` in `src/geometry/bevel/inputs.rs`, see [`EXTERNAL`]).
//! The names of the `[analyses]` table itself are `Analyses::KNOWN`.
//!
//! The roots carry the pair kind that reads them (`RawScene`: spur/helical,
//! `RawBevelScene`: bevel/hypoid), passed down to every struct they reach.
//!
//! **Sections.** A struct's section in `docs/scene.md` is a heading that
//! names one of its tables as `[table]` (`[pinion.micro]`; the top level is
//! the heading containing [`TOP_LEVEL`]) and does not carry the other pair
//! kind's marker ([`MARKERS`]: `spur/helical`, `bevel/hypoid`); a table read
//! by both kinds through different structs (`[pair]`, `[pinion]`) has one
//! heading per kind, each with its marker.
//!
//! **Key tables.** A section documents a key in a markdown table whose
//! header's first cell is `key`: the key in backticks in a row's first cell.
//!
//! Failures:
//! * a key that no key table of its struct's section lists (struct, field,
//!   file:line), with the coverage (keys found / keys documented);
//! * a struct deriving `Deserialize` in `src/scene` that is neither reached
//!   from a root nor in [`MAPPED`], or whose table has no section;
//! * a key in a key table that is not a key of the section's structs (the
//!   document may not list keys that do not exist);
//! * an example scene block in the document that differs from the paper
//!   scene file it links (`examples_are_the_paper_scenes`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use syn::meta::ParseNestedMeta;
use syn::punctuated::Punctuated;
use syn::visit::{self, Visit};
use syn::{Attribute, GenericArgument, LitStr, PathArguments, Token, Type};

/// The document, relative to the package.
const DOC: &str = "docs/scene.md";

/// The folder whose `*.rs` files define the scene keys.
const SCENE_DIR: &str = "src/scene";

/// The heading of the top-level tables' section.
const TOP_LEVEL: &str = "Top-level tables";

/// The pair kinds: which reader (and so which structs) a table belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Kind {
    /// `RawScene`: spur and helical pairs.
    Cylindrical,
    /// `RawBevelScene`: spiral bevel and hypoid pairs.
    Bevel,
}

/// The marker of each kind in a section heading.
const MARKERS: [(Kind, &str); 2] = [
    (Kind::Cylindrical, "spur/helical"),
    (Kind::Bevel, "bevel/hypoid"),
];

const BOTH: &[Kind] = &[Kind::Cylindrical, Kind::Bevel];

/// A struct read into a table: (struct, table path, kinds); `""` is the
/// top level.
type Mapping = (&'static str, &'static str, &'static [Kind]);

/// Structs whose table is not derived from a field type.
const MAPPED: &[Mapping] = &[
    // the readers' roots (`parse_scene`, `parse_any_scene`)
    ("RawScene", "", &[Kind::Cylindrical]),
    ("RawBevelScene", "", &[Kind::Bevel]),
    // `bevel_kind`: `[pair] kind` peeked at before either reader runs
    ("Peek", "", BOTH),
    // `analyses()`: each analysis's table by name from a map of TOML values
    ("MeshAnalysis", "analyses.mesh", BOTH),
    ("ComplianceAnalysis", "analyses.compliance", BOTH),
    ("ContactAnalysis", "analyses.contact", BOTH),
    ("LtcaAnalysis", "analyses.ltca", BOTH),
    ("LubricationAnalysis", "analyses.lubrication", BOTH),
    // `[blank]` is a map of TOML values read by `BlankInputs::from_value`
    ("BlankInputs", "blank", &[Kind::Bevel]),
];

/// Structs outside [`SCENE_DIR`] whose fields are scene keys: (file, struct).
const EXTERNAL: &[(&str, &str)] = &[("src/geometry/bevel/inputs.rs", "BlankInputs")];

/// One key of a struct.
#[derive(Clone, Debug)]
struct Key {
    /// The field (as written in Rust).
    field: String,
    /// The TOML key (renamed) and its aliases.
    names: Vec<String>,
    /// `file:line` of the field.
    at: String,
}

/// A field's nested struct: its type name, the path segments it adds
/// (`<name>` for a map) and whether it is flattened.
#[derive(Clone, Debug)]
struct Nested {
    ty: String,
    segments: Vec<String>,
    flatten: bool,
    /// The field's key (the path segment, unless flattened).
    key: String,
}

/// A struct deriving `Deserialize`.
#[derive(Clone, Debug, Default)]
struct Struct {
    name: String,
    at: String,
    keys: Vec<Key>,
    nested: Vec<Nested>,
}

/// What one file holds.
#[derive(Default)]
struct FileItems {
    structs: Vec<Struct>,
    /// `Analyses::KNOWN` (and any other associated `KNOWN` list).
    known: Option<(Vec<String>, String)>,
}

/// The serde attributes the keys depend on.
#[derive(Default)]
struct SerdeAttrs {
    rename: Option<String>,
    rename_all: Option<String>,
    aliases: Vec<String>,
    flatten: bool,
    skip: bool,
}

/// The deserialize name of `rename = "x"` or `rename(deserialize = "x")`.
fn deserialize_name(m: &ParseNestedMeta) -> syn::Result<Option<String>> {
    if m.input.peek(Token![=]) {
        return Ok(Some(m.value()?.parse::<LitStr>()?.value()));
    }
    let mut out = None;
    m.parse_nested_meta(|inner| {
        let v = inner.value()?.parse::<LitStr>()?.value();
        if inner.path.is_ident("deserialize") {
            out = Some(v);
        }
        Ok(())
    })?;
    Ok(out)
}

/// Consumes a serde attribute the keys do not depend on (`default`,
/// `default = "f"`, `bound(…)`, …).
fn skip_meta(m: &ParseNestedMeta) -> syn::Result<()> {
    if m.input.peek(Token![=]) {
        m.value()?.parse::<syn::Expr>()?;
    } else if m.input.peek(syn::token::Paren) {
        m.parse_nested_meta(|inner| skip_meta(&inner))?;
    }
    Ok(())
}

fn serde_attrs(attrs: &[Attribute]) -> syn::Result<SerdeAttrs> {
    let mut s = SerdeAttrs::default();
    for a in attrs.iter().filter(|a| a.path().is_ident("serde")) {
        a.parse_nested_meta(|m| {
            let name = m.path.get_ident().map(ToString::to_string);
            match name.as_deref() {
                Some("rename") => s.rename = deserialize_name(&m)?.or(s.rename.take()),
                Some("rename_all") => s.rename_all = deserialize_name(&m)?.or(s.rename_all.take()),
                Some("alias") => s.aliases.push(m.value()?.parse::<LitStr>()?.value()),
                Some("flatten") => s.flatten = true,
                Some("skip" | "skip_deserializing") => s.skip = true,
                _ => skip_meta(&m)?,
            }
            Ok(())
        })?;
    }
    Ok(s)
}

fn derives_deserialize(attrs: &[Attribute]) -> bool {
    attrs
        .iter()
        .filter(|a| a.path().is_ident("derive"))
        .any(|a| {
            a.parse_args_with(Punctuated::<syn::Path, Token![,]>::parse_terminated)
                .is_ok_and(|paths| {
                    paths
                        .iter()
                        .any(|p| p.segments.last().is_some_and(|s| s.ident == "Deserialize"))
                })
        })
}

fn is_cfg_test(attrs: &[Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg")
            && a.meta
                .require_list()
                .is_ok_and(|l| l.tokens.to_string().trim() == "test")
    })
}

/// A field name under serde's `rename_all` rule (fields are snake_case).
fn rename_rule(field: &str, rule: &str) -> Result<String, String> {
    let pascal = || -> String {
        field
            .split('_')
            .map(|w| {
                let mut c = w.chars();
                c.next()
                    .map(|f| f.to_uppercase().chain(c).collect::<String>())
                    .unwrap_or_default()
            })
            .collect()
    };
    Ok(match rule {
        "snake_case" => field.to_string(),
        "lowercase" => field.to_ascii_lowercase(),
        "UPPERCASE" | "SCREAMING_SNAKE_CASE" => field.to_ascii_uppercase(),
        "kebab-case" => field.replace('_', "-"),
        "SCREAMING-KEBAB-CASE" => field.to_ascii_uppercase().replace('_', "-"),
        "PascalCase" => pascal(),
        "camelCase" => {
            let p = pascal();
            let mut c = p.chars();
            c.next()
                .map(|f| f.to_lowercase().chain(c).collect())
                .unwrap_or_default()
        }
        other => return Err(format!("unknown serde rename_all rule {other:?}")),
    })
}

/// The struct a field's type nests, through `Option`, `Spanned`, `Box`,
/// `Vec` and maps (a map adds the segment `<name>`).
fn nested_type(ty: &Type, segments: &mut Vec<String>) -> Option<String> {
    let Type::Path(p) = ty else {
        return None;
    };
    let last = p.path.segments.last()?;
    let args: Vec<&Type> = match &last.arguments {
        PathArguments::AngleBracketed(a) => a
            .args
            .iter()
            .filter_map(|g| match g {
                GenericArgument::Type(t) => Some(t),
                _ => None,
            })
            .collect(),
        _ => Vec::new(),
    };
    match last.ident.to_string().as_str() {
        "Option" | "Spanned" | "Box" | "Vec" => nested_type(args.first()?, segments),
        "BTreeMap" | "HashMap" | "IndexMap" => {
            segments.push("<name>".into());
            nested_type(args.get(1)?, segments)
        }
        name => Some(name.to_string()),
    }
}

/// 1-based line of the first line at or after `from` for which `hit` holds.
fn line_where(text: &str, from: usize, hit: impl Fn(&str) -> bool) -> Option<usize> {
    text.lines()
        .enumerate()
        .skip(from.saturating_sub(1))
        .find(|(_, l)| hit(l))
        .map(|(i, _)| i + 1)
}

/// Whether `line` contains `word` not preceded or followed by an identifier character.
fn has_word(line: &str, word: &str) -> bool {
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    line.match_indices(word).any(|(i, _)| {
        let before = line[..i].chars().next_back().is_none_or(|c| !ident(c));
        let after = line[i + word.len()..]
            .chars()
            .next()
            .is_none_or(|c| !ident(c));
        before && after
    })
}

/// Whether `line` declares field `field` (`field:`, `pub(super) field:`).
fn declares_field(line: &str, field: &str) -> bool {
    let mut t = line.trim_start();
    if let Some(rest) = t.strip_prefix("pub") {
        t = rest.trim_start();
        if t.starts_with('(') {
            t = t.split_once(')').map_or("", |(_, r)| r).trim_start();
        }
    }
    t.strip_prefix(field)
        .is_some_and(|r| r.trim_start().starts_with(':'))
}

struct Collector<'a> {
    file: &'a str,
    text: &'a str,
    items: FileItems,
    errors: Vec<String>,
}

impl Collector<'_> {
    fn struct_of(&self, s: &syn::ItemStruct) -> Result<Struct, String> {
        let name = s.ident.to_string();
        let decl = format!("struct {name}");
        let line = line_where(self.text, 1, |l| {
            !l.trim_start().starts_with("//") && has_word(l, &decl)
        })
        .unwrap_or(1);
        let at = |l: usize| format!("{}:{l}", self.file);
        let attrs = serde_attrs(&s.attrs).map_err(|e| format!("{}: {name}: {e}", at(line)))?;
        let mut out = Struct {
            name: name.clone(),
            at: at(line),
            ..Default::default()
        };
        for f in &s.fields {
            let Some(ident) = &f.ident else {
                return Err(format!("{}: {name}: a tuple struct has no keys", at(line)));
            };
            let written = ident.to_string();
            let field = syn::ext::IdentExt::unraw(ident).to_string();
            let fl = line_where(self.text, line, |l| declares_field(l, &written)).unwrap_or(line);
            let fa =
                serde_attrs(&f.attrs).map_err(|e| format!("{}: {name}.{field}: {e}", at(fl)))?;
            if fa.skip {
                continue;
            }
            let key = match (&fa.rename, &attrs.rename_all) {
                (Some(r), _) => r.clone(),
                (None, Some(rule)) => {
                    rename_rule(&field, rule).map_err(|e| format!("{}: {name}: {e}", at(line)))?
                }
                (None, None) => field.clone(),
            };
            let mut segments = Vec::new();
            if let Some(ty) = nested_type(&f.ty, &mut segments) {
                out.nested.push(Nested {
                    ty,
                    segments,
                    flatten: fa.flatten,
                    key: key.clone(),
                });
            }
            if fa.flatten {
                continue;
            }
            let mut names = vec![key];
            names.extend(fa.aliases);
            out.keys.push(Key {
                field,
                names,
                at: at(fl),
            });
        }
        Ok(out)
    }
}

/// The string literals of an expression.
struct Strings(Vec<String>);

impl<'ast> Visit<'ast> for Strings {
    fn visit_lit_str(&mut self, s: &'ast LitStr) {
        self.0.push(s.value());
    }
}

impl<'ast> Visit<'ast> for Collector<'_> {
    fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
        if !is_cfg_test(&m.attrs) {
            visit::visit_item_mod(self, m);
        }
    }

    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        if !f.attrs.iter().any(|a| a.path().is_ident("test")) && !is_cfg_test(&f.attrs) {
            visit::visit_item_fn(self, f);
        }
    }

    fn visit_item_struct(&mut self, s: &'ast syn::ItemStruct) {
        if derives_deserialize(&s.attrs) && !is_cfg_test(&s.attrs) {
            match self.struct_of(s) {
                Ok(st) => self.items.structs.push(st),
                Err(e) => self.errors.push(e),
            }
        }
        visit::visit_item_struct(self, s);
    }

    fn visit_impl_item_const(&mut self, c: &'ast syn::ImplItemConst) {
        if c.ident == "KNOWN" {
            let mut strings = Strings(Vec::new());
            strings.visit_expr(&c.expr);
            let line = line_where(self.text, 1, |l| l.contains("const KNOWN")).unwrap_or(1);
            self.items.known = Some((strings.0, format!("{}:{line}", self.file)));
        }
        visit::visit_impl_item_const(self, c);
    }
}

/// The structs of one file (`file` names it in messages).
fn collect(file: &str, text: &str) -> Result<FileItems, String> {
    let ast = syn::parse_file(text).map_err(|e| format!("{file}: {e}"))?;
    let mut c = Collector {
        file,
        text,
        items: FileItems::default(),
        errors: Vec::new(),
    };
    c.visit_file(&ast);
    if c.errors.is_empty() {
        Ok(c.items)
    } else {
        Err(c.errors.join("\n"))
    }
}

/// A section of the document: its heading and its key-table rows.
#[derive(Debug)]
struct Section {
    /// 1-based line of the heading.
    line: usize,
    heading: String,
    /// Key-table rows: (line, keys in backticks in the first cell).
    rows: Vec<(usize, Vec<String>)>,
}

impl Section {
    fn keys(&self) -> BTreeSet<&str> {
        self.rows
            .iter()
            .flat_map(|(_, k)| k.iter().map(String::as_str))
            .collect()
    }

    fn label(&self) -> String {
        format!("{DOC}:{} \"{}\"", self.line, self.heading)
    }
}

/// The texts in backticks of `s`.
fn backticked(s: &str) -> Vec<String> {
    s.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// The first cell of a table row (`| a | b |` → `a`).
fn first_cell(row: &str) -> &str {
    row.trim()
        .trim_start_matches('|')
        .split('|')
        .next()
        .unwrap_or("")
        .trim()
}

/// The document's sections (code fences skipped); a section runs to the
/// next heading of any level.
fn sections(doc: &str) -> Vec<Section> {
    let mut out: Vec<Section> = Vec::new();
    let mut fence = false;
    let mut in_key_table = false;
    let mut header_seen = false;
    for (i, line) in doc.lines().enumerate() {
        let t = line.trim_start();
        if t.starts_with("```") {
            fence = !fence;
            continue;
        }
        if fence {
            continue;
        }
        if t.starts_with('#') {
            out.push(Section {
                line: i + 1,
                heading: t.trim_start_matches('#').trim().to_string(),
                rows: Vec::new(),
            });
            in_key_table = false;
            header_seen = false;
            continue;
        }
        if !t.starts_with('|') {
            in_key_table = false;
            header_seen = false;
            continue;
        }
        if !header_seen {
            header_seen = true;
            in_key_table = first_cell(t).eq_ignore_ascii_case("key");
            continue;
        }
        let cell = first_cell(t);
        if !in_key_table || cell.chars().all(|c| matches!(c, '-' | ':' | ' ')) {
            continue;
        }
        if let Some(s) = out.last_mut() {
            s.rows.push((i + 1, backticked(cell)));
        }
    }
    out
}

/// Whether section `s` documents table `path` for `kind`.
fn documents(s: &Section, path: &str, kind: Kind) -> bool {
    let names = if path.is_empty() {
        s.heading.contains(TOP_LEVEL)
    } else {
        s.heading.contains(&format!("[{path}]"))
    };
    let other = MARKERS
        .iter()
        .any(|(k, m)| *k != kind && s.heading.contains(m));
    names && !other
}

/// Struct → the (table path, kind) pairs it is read into.
type Reached = BTreeMap<String, BTreeSet<(String, Kind)>>;

/// Everything the checks need: the structs by name and where each is read.
struct Model {
    structs: BTreeMap<String, Struct>,
    reached: Reached,
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A source file: its name (relative to the package) and text.
type Source = (String, String);

/// The model of the package's sources ([`SCENE_DIR`], [`EXTERNAL`], [`MAPPED`]).
fn model() -> Result<Model, Vec<String>> {
    let read = |f: &str| {
        let text = std::fs::read_to_string(root().join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        (f.to_string(), text)
    };
    let mut files: Vec<String> = std::fs::read_dir(root().join(SCENE_DIR))
        .unwrap_or_else(|e| panic!("{SCENE_DIR}: {e}"))
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".rs"))
        .map(|n| format!("{SCENE_DIR}/{n}"))
        .collect();
    files.sort();
    let scene: Vec<Source> = files.iter().map(|f| read(f)).collect();
    let external: Vec<(Source, &str)> = EXTERNAL.iter().map(|(f, s)| (read(f), *s)).collect();
    model_of(&scene, &external, MAPPED)
}

/// The structs of `scene` (every `Deserialize` struct) and `external`
/// (the named struct of each file), and the tables each is read into from
/// the roots and tables of `mapped`.
fn model_of(
    scene: &[Source],
    external: &[(Source, &str)],
    mapped: &[Mapping],
) -> Result<Model, Vec<String>> {
    let mut errors = Vec::new();
    let mut structs: BTreeMap<String, Struct> = BTreeMap::new();
    let mut scene_structs = Vec::new();
    let mut known = None;
    let mut add = |s: Struct, errors: &mut Vec<String>| {
        if let Some(old) = structs.get(&s.name) {
            errors.push(format!(
                "{}: struct {} is defined at {} too: the test keys structs by name",
                s.at, s.name, old.at
            ));
        }
        structs.insert(s.name.clone(), s);
    };
    for (f, text) in scene {
        match collect(f, text) {
            Ok(items) => {
                if items.known.is_some() {
                    known = items.known;
                }
                for s in items.structs {
                    scene_structs.push(s.name.clone());
                    add(s, &mut errors);
                }
            }
            Err(e) => errors.push(e),
        }
    }
    for ((f, text), name) in external {
        match collect(f, text) {
            Ok(items) => match items.structs.into_iter().find(|s| s.name == *name) {
                Some(s) => add(s, &mut errors),
                None => errors.push(format!(
                    "{f}: EXTERNAL names struct {name}, which is not there (or does not derive Deserialize)"
                )),
            },
            Err(e) => errors.push(e),
        }
    }

    // the names of `[analyses]`: `Analyses::KNOWN`, each mapped to its struct
    let analyses: Vec<&str> = mapped
        .iter()
        .filter_map(|(_, p, _)| p.strip_prefix("analyses."))
        .collect();
    match known {
        None if analyses.is_empty() => {}
        None => errors.push(format!(
            "{SCENE_DIR}: no `const KNOWN` (the names of [analyses]) found"
        )),
        Some((names, at)) => {
            for n in &names {
                if !analyses.contains(&n.as_str()) {
                    errors.push(format!(
                        "{at}: analysis `{n}` of Analyses::KNOWN has no struct in MAPPED (tests/scene_keys.rs) as `analyses.{n}`"
                    ));
                }
            }
            let keys = names
                .iter()
                .map(|n| Key {
                    field: n.clone(),
                    names: vec![n.clone()],
                    at: at.clone(),
                })
                .collect();
            add(
                Struct {
                    name: "Analyses::KNOWN".into(),
                    at: at.clone(),
                    keys,
                    nested: Vec::new(),
                },
                &mut errors,
            );
        }
    }

    // where each struct is read: from MAPPED down the field types
    let mut reached = Reached::new();
    let mut queue: Vec<(String, String, Kind)> = mapped
        .iter()
        .flat_map(|(s, p, kinds)| kinds.iter().map(|k| (s.to_string(), p.to_string(), *k)))
        .collect();
    if structs.contains_key("Analyses::KNOWN") {
        queue.extend(
            BOTH.iter()
                .map(|k| ("Analyses::KNOWN".into(), "analyses".into(), *k)),
        );
    }
    while let Some((name, path, kind)) = queue.pop() {
        let Some(s) = structs.get(&name) else {
            errors.push(format!(
                "MAPPED (tests/scene_keys.rs) names struct {name}, which no scanned file defines with derive(Deserialize)"
            ));
            continue;
        };
        if !reached
            .entry(name.clone())
            .or_default()
            .insert((path.clone(), kind))
        {
            continue;
        }
        for n in s.nested.iter().filter(|n| structs.contains_key(&n.ty)) {
            let sub = if n.flatten {
                path.clone()
            } else {
                let mut parts: Vec<&str> = Vec::new();
                if !path.is_empty() {
                    parts.push(&path);
                }
                parts.push(&n.key);
                parts.extend(n.segments.iter().map(String::as_str));
                parts.join(".")
            };
            queue.push((n.ty.clone(), sub, kind));
        }
    }
    for name in &scene_structs {
        if !reached.contains_key(name) {
            errors.push(format!(
                "{}: struct {name} derives Deserialize but is read into no table: no root reaches it through its field types and MAPPED (tests/scene_keys.rs) does not name it",
                structs[name].at
            ));
        }
    }
    if errors.is_empty() {
        Ok(Model { structs, reached })
    } else {
        Err(errors)
    }
}

fn kind_name(k: Kind) -> &'static str {
    MARKERS.iter().find(|(m, _)| *m == k).map_or("", |(_, n)| n)
}

fn tables(paths: &BTreeSet<(String, Kind)>, kind: Kind) -> String {
    paths
        .iter()
        .filter(|(_, k)| *k == kind)
        .map(|(p, _)| {
            if p.is_empty() {
                "the top level".to_string()
            } else {
                format!("[{p}]")
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn doc_text() -> String {
    std::fs::read_to_string(root().join(DOC)).unwrap_or_else(|e| panic!("{DOC}: {e}"))
}

/// Struct → its sections (indices into the document's sections).
type StructSections = BTreeMap<String, BTreeSet<usize>>;

/// Each struct's sections, and the errors of structs without one.
fn struct_sections(m: &Model, secs: &[Section]) -> (StructSections, Vec<String>) {
    let mut out = StructSections::new();
    let mut errors = Vec::new();
    for (name, paths) in &m.reached {
        let kinds: BTreeSet<Kind> = paths.iter().map(|(_, k)| *k).collect();
        for kind in kinds {
            let found: Vec<usize> = (0..secs.len())
                .filter(|&i| {
                    paths
                        .iter()
                        .any(|(p, k)| *k == kind && documents(&secs[i], p, kind))
                })
                .collect();
            if found.is_empty() {
                errors.push(format!(
                    "{}: struct {name} ({}) is read into {} but {DOC} has no section for it (a heading naming the table as `[table]` without the marker \"{}\"{})",
                    m.structs[name].at,
                    kind_name(kind),
                    tables(paths, kind),
                    MARKERS.iter().find(|(k, _)| *k != kind).map_or("", |(_, n)| n),
                    if tables(paths, kind) == "the top level" {
                        format!("; the top level's heading contains \"{TOP_LEVEL}\"")
                    } else {
                        String::new()
                    }
                ));
            }
            out.entry(name.clone()).or_default().extend(found);
        }
    }
    (out, errors)
}

#[test]
fn every_scene_key_is_documented() {
    let m = model().unwrap_or_else(|e| panic!("scene keys: {}", e.join("\n")));
    let doc = doc_text();
    let secs = sections(&doc);
    let (by_struct, mut errors) = struct_sections(&m, &secs);
    let (mut found, mut documented) = (0, 0);
    for (name, idx) in &by_struct {
        let s = &m.structs[name];
        for key in &s.keys {
            found += 1;
            if idx.is_empty() {
                continue; // the struct's missing section is the error
            }
            let missing: Vec<String> = idx
                .iter()
                .map(|&i| &secs[i])
                .filter(|sec| !key.names.iter().any(|n| sec.keys().contains(n.as_str())))
                .map(Section::label)
                .collect();
            if missing.is_empty() {
                documented += 1;
            } else {
                errors.push(format!(
                    "{}: `{}` ({name}.{}) is in no key-table row of {}",
                    key.at,
                    key.names[0],
                    key.field,
                    missing.join(", ")
                ));
            }
        }
    }
    let tables: BTreeSet<usize> = by_struct.values().flatten().copied().collect();
    let coverage = format!(
        "{documented} of {found} keys documented ({} structs, {} sections of {DOC})",
        by_struct.len(),
        tables.len()
    );
    eprintln!("scene keys: {coverage}");
    assert!(
        errors.is_empty(),
        "scene keys: {coverage}; {} problem(s):\n{}",
        errors.len(),
        errors.join("\n")
    );
}

#[test]
fn documented_keys_exist() {
    let m = model().unwrap_or_else(|e| panic!("scene keys: {}", e.join("\n")));
    let doc = doc_text();
    let secs = sections(&doc);
    let (by_struct, _) = struct_sections(&m, &secs);
    let mut allowed: BTreeMap<usize, (BTreeSet<&str>, Vec<&str>)> = BTreeMap::new();
    for (name, idx) in &by_struct {
        for &i in idx {
            let e = allowed.entry(i).or_default();
            e.0.extend(
                m.structs[name]
                    .keys
                    .iter()
                    .flat_map(|k| k.names.iter().map(String::as_str)),
            );
            e.1.push(name);
        }
    }
    let mut errors = Vec::new();
    let mut rows = 0;
    for (i, sec) in secs.iter().enumerate() {
        let Some((ok, structs)) = allowed.get(&i) else {
            if let Some((line, _)) = sec.rows.first() {
                rows += sec.rows.len();
                errors.push(format!(
                    "{DOC}:{line}: {} key-table row(s) in section \"{}\", which documents no table a struct of {SCENE_DIR} is read into (its heading names no such `[table]`)",
                    sec.rows.len(),
                    sec.heading
                ));
            }
            continue;
        };
        for (line, keys) in &sec.rows {
            rows += 1;
            if keys.is_empty() {
                errors.push(format!(
                    "{DOC}:{line}: a key-table row without a `key` in its first cell"
                ));
            }
            for k in keys.iter().filter(|k| !ok.contains(k.as_str())) {
                errors.push(format!(
                    "{DOC}:{line}: `{k}` in section \"{}\" is not a key of {}",
                    sec.heading,
                    structs.join(", ")
                ));
            }
        }
    }
    assert!(
        errors.is_empty(),
        "{DOC}: {} problem(s) in its {rows} key-table rows (keys that do not exist):\n{}",
        errors.len(),
        errors.join("\n")
    );
}

/// The example blocks of the document are the paper scenes they link (a
/// `toml` fence right after a line linking a `.toml` file).
#[test]
fn examples_are_the_paper_scenes() {
    let doc = doc_text();
    let lines: Vec<&str> = doc.lines().collect();
    let mut checked = Vec::new();
    for (i, w) in lines.windows(2).enumerate() {
        let link = w[0]
            .split("](")
            .nth(1)
            .and_then(|r| r.split(')').next())
            .filter(|t| t.ends_with(".toml"));
        let (Some(target), true) = (link, w[1].trim() == "```toml") else {
            continue;
        };
        let body: Vec<&str> = lines[i + 2..]
            .iter()
            .take_while(|l| l.trim() != "```")
            .copied()
            .collect();
        let file = root().join("docs").join(target);
        let text = std::fs::read_to_string(&file)
            .unwrap_or_else(|e| panic!("{DOC}:{}: {}: {e}", i + 1, file.display()));
        let want: Vec<&str> = text.lines().collect();
        assert_eq!(
            body,
            want,
            "{DOC}:{}: the example differs from {target}: copy the file again",
            i + 3
        );
        checked.push(target);
    }
    assert!(
        checked.len() >= 2,
        "{DOC}: expected an example scene of each pair kind, found {checked:?}"
    );
}

#[test]
fn checker_reads_serde_attributes() {
    let src = r#"
        #[derive(Deserialize)]
        #[serde(deny_unknown_fields, rename_all = "kebab-case")]
        struct RawA {
            plain_key: Option<Spanned<f64>>,
            #[serde(rename = "Sigma_deg")]
            sigma: f64,
            #[serde(default, alias = "old_name")]
            pub(super) new_name: u32,
            #[serde(flatten)]
            inner: RawInner,
            #[serde(skip)]
            cache: Vec<f64>,
            #[serde(rename(deserialize = "in", serialize = "x"))]
            r#type: BTreeMap<String, RawInner>,
        }
        #[derive(Clone, serde::Deserialize)]
        struct RawInner { deep_key: bool }
        struct NotSerde { x: f64 }
        #[cfg(test)]
        mod tests { #[derive(Deserialize)] struct RawTest { t: f64 } }
        fn peek() { #[derive(Deserialize)] struct Peek { pair: Option<RawInner> } }
    "#;
    let items = collect("x.rs", src).unwrap();
    let names: Vec<&str> = items.structs.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["RawA", "RawInner", "Peek"]);
    let a = &items.structs[0];
    let keys: Vec<Vec<String>> = a.keys.iter().map(|k| k.names.clone()).collect();
    assert_eq!(
        keys,
        [
            vec!["plain-key".to_string()],
            vec!["Sigma_deg".into()],
            vec!["new-name".into(), "old_name".into()],
            vec!["in".into()],
        ]
    );
    assert_eq!(a.keys[2].at, "x.rs:9");
    assert_eq!(a.at, "x.rs:4");
    let nested: Vec<(&str, bool, &str, &[String])> = a
        .nested
        .iter()
        .filter(|n| n.ty.starts_with("Raw"))
        .map(|n| (n.ty.as_str(), n.flatten, n.key.as_str(), &n.segments[..]))
        .collect();
    let map = ["<name>".to_string()];
    assert_eq!(
        nested,
        [
            ("RawInner", true, "inner", &[][..]),
            ("RawInner", false, "in", &map[..]),
        ]
    );
}

#[test]
fn checker_finds_sections_and_key_rows() {
    let doc = "# T\n\n## Top-level tables\n\n| key | type |\n|---|---|\n| `pair` | table |\n\n```toml\n# [pair] inside a fence\n| `no` |\n```\n\n### `[pair]` (spur/helical)\n\n| Key | x |\n|:--|--|\n| `kind` | string |\n\n| value | meaning |\n|---|---|\n| `spur` | not a key |\n\n### `[pair]` (bevel/hypoid)\n";
    let s = sections(doc);
    let heads: Vec<&str> = s.iter().map(|s| s.heading.as_str()).collect();
    assert_eq!(
        heads,
        [
            "T",
            "Top-level tables",
            "`[pair]` (spur/helical)",
            "`[pair]` (bevel/hypoid)"
        ]
    );
    assert_eq!(s[1].rows, [(7, vec!["pair".to_string()])]);
    assert_eq!(s[2].rows, [(18, vec!["kind".to_string()])]);
    assert!(documents(&s[1], "", Kind::Bevel));
    assert!(documents(&s[2], "pair", Kind::Cylindrical));
    assert!(!documents(&s[2], "pair", Kind::Bevel));
    assert!(documents(&s[3], "pair", Kind::Bevel));
    assert!(!documents(&s[2], "pair.micro", Kind::Cylindrical));
}

#[test]
fn rename_rules() {
    let r = |rule| rename_rule("young_modulus_mpa", rule).unwrap();
    assert_eq!(r("camelCase"), "youngModulusMpa");
    assert_eq!(r("PascalCase"), "YoungModulusMpa");
    assert_eq!(r("SCREAMING-KEBAB-CASE"), "YOUNG-MODULUS-MPA");
    assert!(rename_rule("a", "Title Case").is_err());
}

#[test]
fn checker_derives_tables_and_refuses_unread_structs() {
    let scene = r#"
        #[derive(Deserialize)]
        struct RawRoot { pair: RawPair, materials: BTreeMap<String, RawMat>, #[serde(flatten)] extra: RawExtra }
        #[derive(Deserialize)]
        struct RawPair { kind: Spanned<String>, micro: Option<Spanned<RawMicro>> }
        #[derive(Deserialize)]
        struct RawMicro { tip_um: f64 }
        #[derive(Deserialize)]
        struct RawMat { e_mpa: f64 }
        #[derive(Deserialize)]
        struct RawExtra { note: String }
    "#;
    let src = |t: &str| vec![("s.rs".to_string(), t.to_string())];
    let mapped: &[Mapping] = &[("RawRoot", "", &[Kind::Cylindrical])];
    let m = model_of(&src(scene), &[], mapped).unwrap();
    let at =
        |name: &str| -> Vec<String> { m.reached[name].iter().map(|(p, _)| p.clone()).collect() };
    assert_eq!(at("RawPair"), ["pair"]);
    assert_eq!(at("RawMicro"), ["pair.micro"]);
    assert_eq!(at("RawMat"), ["materials.<name>"]);
    assert_eq!(at("RawExtra"), [""]);
    let root: Vec<&str> = m.structs["RawRoot"]
        .keys
        .iter()
        .map(|k| k.names[0].as_str())
        .collect();
    assert_eq!(root, ["pair", "materials"]);
    // a Deserialize struct no root reaches, and a root that does not exist
    let orphan = format!("{scene}\n#[derive(Deserialize)]\nstruct RawOrphan {{ x: f64 }}\n");
    let Err(e) = model_of(&src(&orphan), &[], mapped) else {
        panic!("an unread struct passed");
    };
    let e = e.join("\n");
    assert!(
        e.contains("s.rs:14: struct RawOrphan derives Deserialize but is read into no table"),
        "{e}"
    );
    let Err(e) = model_of(&src(scene), &[], &[("RawNone", "", BOTH)]) else {
        panic!("a missing root passed");
    };
    let e = e.join("\n");
    assert!(
        e.contains("names struct RawNone") && e.contains("struct RawRoot"),
        "{e}"
    );
}
