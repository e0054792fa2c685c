//! Stage 1: the syntax tree of a `bond_graph!` block and its parser.
//!
//! The tree mirrors the text one to one and keeps every span, so later stages can point
//! at the user's words. Nothing is resolved here: names are still identifiers.

use proc_macro2::{Span, TokenStream, TokenTree};
use syn::ext::IdentExt;
use syn::parse::{Parse, ParseStream};
use syn::spanned::Spanned;
use syn::{braced, bracketed, Attribute, Expr, Ident, LitInt, Token, Visibility};

/// Words with a meaning of their own in a `bond_graph!` block.
pub mod kw {
    syn::custom_keyword!(model);
    syn::custom_keyword!(submodel);
    syn::custom_keyword!(param);
    syn::custom_keyword!(input);
    syn::custom_keyword!(init);
    syn::custom_keyword!(output);
    syn::custom_keyword!(state);
    syn::custom_keyword!(der);
    syn::custom_keyword!(inverse);
}

/// Element kinds as written, for parsing and for error messages.
pub const ELEMENT_KINDS: &str = "Se, Sf, MSe, MSf, C, I, R, TF, GY, MTF, MGY, 0, 1";

/// The shape of a value: a number, an n-vector, or an r×c matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// `f64`
    Scalar,
    /// `[f64; n]`, `Vector3`
    Vector(usize),
    /// `[[f64; c]; r]` (rows first), `Matrix3`
    Matrix(usize, usize),
}

impl Shape {
    /// How many numbers it holds.
    pub fn len(self) -> usize {
        match self {
            Shape::Scalar => 1,
            Shape::Vector(n) => n,
            Shape::Matrix(r, c) => r * c,
        }
    }

    /// The shape of an n-dimensional bond variable.
    pub fn of_dimension(n: usize) -> Self {
        if n == 1 {
            Shape::Scalar
        } else {
            Shape::Vector(n)
        }
    }
}

/// `: Type` after a name: `f64`, `Vector3`, `Matrix3`, `[f64; N]` or `[[f64; C]; R]`.
fn parse_shape(input: ParseStream) -> syn::Result<Shape> {
    let ty: syn::Type = input.parse()?;
    shape_of(&ty).ok_or_else(|| {
        syn::Error::new_spanned(
            &ty,
            "expected a value type: `f64`, `Vector3`, `Matrix3`, `[f64; N]` or `[[f64; C]; R]`",
        )
    })
}

fn shape_of(ty: &syn::Type) -> Option<Shape> {
    let length = |len: &Expr| match len {
        Expr::Lit(syn::ExprLit {
            lit: syn::Lit::Int(n),
            ..
        }) => n.base10_parse::<usize>().ok().filter(|&n| n > 0),
        _ => None,
    };
    match ty {
        syn::Type::Path(path) if path.path.is_ident("f64") => Some(Shape::Scalar),
        syn::Type::Path(path) if path.path.is_ident("Vector3") => Some(Shape::Vector(3)),
        syn::Type::Path(path) if path.path.is_ident("Matrix3") => Some(Shape::Matrix(3, 3)),
        syn::Type::Array(array) => match (shape_of(&array.elem)?, length(&array.len)?) {
            (Shape::Scalar, n) => Some(Shape::Vector(n)),
            (Shape::Vector(c), r) => Some(Shape::Matrix(r, c)),
            _ => None,
        },
        _ => None,
    }
}

fn optional_shape(input: ParseStream) -> syn::Result<Option<Shape>> {
    if input.peek(Token![:]) {
        input.parse::<Token![:]>()?;
        parse_shape(input).map(Some)
    } else {
        Ok(None)
    }
}

/// `[n]` after an element kind: the dimension of its bonds.
fn optional_dimension(input: ParseStream) -> syn::Result<Option<(usize, Span)>> {
    if !input.peek(syn::token::Bracket) {
        return Ok(None);
    }
    let inner;
    bracketed!(inner in input);
    parse_group(&inner, |inner| {
        let n: LitInt = inner.parse()?;
        let value: usize = n.base10_parse()?;
        if value == 0 || !inner.is_empty() {
            return Err(syn::Error::new(
                n.span(),
                "a dimension is a positive number: `I[3] body = m;`",
            ));
        }
        Ok(Some((value, n.span())))
    })
}

/// Everything in one `bond_graph! { ... }` invocation: one or more models.
pub struct File {
    /// The models in the order written.
    pub models: Vec<ModelDef>,
}

/// `/// doc  pub model Name { statements }`
pub struct ModelDef {
    /// Outer attributes, doc comments included.
    pub attrs: Vec<Attribute>,
    /// Visibility of the generated items.
    pub vis: Visibility,
    /// The model's name.
    pub name: Ident,
    /// The statements that parsed.
    pub stmts: Vec<Stmt>,
    /// Errors from statements that did not parse (each skipped to its `;`) and
    /// mistakes the parser could step over.
    pub errors: Vec<syn::Error>,
    /// Names that statements which failed to parse meant to declare: later stages
    /// stay quiet about them instead of reporting follow-on errors.
    pub poisoned: Vec<Ident>,
    /// The flat names (`crank`, `arm__upper`) of the instances of the standard
    /// library's `RigidBody`, in the order inlined: the model's bodies.
    pub bodies: Vec<String>,
}

/// One statement inside a model.
pub enum Stmt {
    /// `param k = 100.0;`
    Param(ParamDecl),
    /// `C spring = k;`, `R damper { e = c * f * f.abs() };`, `1 v;`
    Element(ElementDecl),
    /// `push -> v -> { mass, spring };`
    Bonds(BondChain),
    /// `init spring.q = 0.01;`
    Init(InitDecl),
    /// `output x = spring.q;`
    Output(OutputDecl),
    /// `state R: Matrix3 = rot_z(theta0);`
    State(StateDecl),
    /// `der R = skew(w.f) * R;`
    Der(DerDecl),
    /// `mode stuck: bool = false;`
    Mode(crate::event_syntax::ModeDecl),
    /// `when ball.q < 0.0 { reinit ball.p = -e * ball.p; }`
    When(crate::event_syntax::WhenDecl),
}

/// A kinematic state: integrated, but not the storage of a bond-graph element.
pub struct StateDecl {
    /// Doc comments: the state's documentation.
    pub attrs: Vec<Attribute>,
    /// The state's name.
    pub name: Ident,
    /// Its shape.
    pub shape: Shape,
    /// The initial value, an expression in parameters.
    pub init: Expr,
    /// Its unit, written `in "m"` after the initial value.
    pub unit: Option<syn::LitStr>,
}

/// The time derivative of a kinematic state.
pub struct DerDecl {
    /// The state.
    pub name: Ident,
    /// dx/dt, an expression in signals, states, parameters and `t`.
    pub expr: Expr,
}

/// A parameter with its default value.
pub struct ParamDecl {
    /// Doc comments (units by convention) and other attributes.
    pub attrs: Vec<Attribute>,
    /// The parameter's name.
    pub name: Ident,
    /// Its shape (`f64` unless declared).
    pub shape: Shape,
    /// The default, an expression in earlier parameters.
    pub default: Expr,
    /// Its unit, written `in "kg"` after the default.
    pub unit: Option<syn::LitStr>,
    /// Declared `input`: set by the host between steps rather than fixed for a run.
    pub input: bool,
}

/// The kind of an element, as the syntax names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElementKind {
    /// `Se`
    Se,
    /// `Sf`
    Sf,
    /// `C`
    C,
    /// `I`
    I,
    /// `R`
    R,
    /// `TF`
    Tf,
    /// `GY`
    Gy,
    /// `0`
    Zero,
    /// `1`
    One,
    /// `Split`: a multibond and its scalar components.
    Split,
}

impl ElementKind {
    /// The kind a word names. The modulated forms (MSe, MSf, MTF, MGY) are the same
    /// kinds: any law may depend on signals, states and time.
    fn from_word(word: &str) -> Option<Self> {
        Some(match word {
            "Se" | "MSe" => ElementKind::Se,
            "Sf" | "MSf" => ElementKind::Sf,
            "C" => ElementKind::C,
            "I" => ElementKind::I,
            "R" => ElementKind::R,
            "TF" | "MTF" => ElementKind::Tf,
            "GY" | "MGY" => ElementKind::Gy,
            "Split" => ElementKind::Split,
            _ => return None,
        })
    }

    /// The kind as written.
    pub fn word(self) -> &'static str {
        match self {
            ElementKind::Se => "Se",
            ElementKind::Sf => "Sf",
            ElementKind::C => "C",
            ElementKind::I => "I",
            ElementKind::R => "R",
            ElementKind::Tf => "TF",
            ElementKind::Gy => "GY",
            ElementKind::Zero => "0",
            ElementKind::One => "1",
            ElementKind::Split => "Split",
        }
    }

    /// The kind as written, modulated or not: `MTF` for a modulated transformer.
    pub fn written(self, modulated: bool) -> &'static str {
        match (self, modulated) {
            (ElementKind::Se, true) => "MSe",
            (ElementKind::Sf, true) => "MSf",
            (ElementKind::Tf, true) => "MTF",
            (ElementKind::Gy, true) => "MGY",
            (kind, _) => kind.word(),
        }
    }

    /// Human description used in messages ("1-junction", "C element").
    pub fn describe(self) -> &'static str {
        match self {
            ElementKind::Se => "effort source Se",
            ElementKind::Sf => "flow source Sf",
            ElementKind::C => "C element",
            ElementKind::I => "I element",
            ElementKind::R => "R element",
            ElementKind::Tf => "transformer TF",
            ElementKind::Gy => "gyrator GY",
            ElementKind::Zero => "0-junction",
            ElementKind::One => "1-junction",
            ElementKind::Split => "splitter",
        }
    }
}

/// `KIND name [= expr | { var = expr, ... }] [, q in "unit"];` (doc comments on a C or
/// I element document its state.)
pub struct ElementDecl {
    /// Doc comments and other attributes.
    pub attrs: Vec<Attribute>,
    /// The kind.
    pub kind: ElementKind,
    /// Written in its modulated form (MSe, MSf, MTF, MGY): the same kind to the
    /// compiler, shown as written.
    pub modulated: bool,
    /// The dimension declared with `[n]`, and where.
    pub dimension: Option<(usize, Span)>,
    /// The element's name.
    pub name: Ident,
    /// Its constitutive law as written.
    pub law: LawSyntax,
    /// A two-port's `inverse = expr`: the inverse of its modulus, for the causality
    /// that needs it.
    pub inverse: Option<Expr>,
    /// `, q in "m"` after the law: the unit of a storage element's state.
    pub state_unit: Option<(Ident, syn::LitStr)>,
}

/// A constitutive law as written.
pub enum LawSyntax {
    /// No law (junctions).
    None,
    /// `= expr`: the linear coefficient (stiffness, mass, resistance, modulus) or a
    /// source's value.
    Linear(Expr),
    /// `{ e = expr, f = expr }`: explicit forms in the element's own variables.
    Forms(Vec<LawForm>),
}

/// `var = expr` inside an element's braces.
pub struct LawForm {
    /// The variable the form computes (`e` or `f`).
    pub var: Ident,
    /// The right-hand side.
    pub expr: Expr,
}

/// `a -> b -[label]-> { c, d };`
pub struct BondChain {
    /// Attributes before the statement (only `#[allow(...)]` of a bond-graph lint is
    /// accepted; see [`crate::allow`]).
    pub attrs: Vec<Attribute>,
    /// The first endpoint.
    pub first: Endpoint,
    /// Each arrow and the endpoint it points at.
    pub links: Vec<(Arrow, Endpoint)>,
}

/// One side of an arrow: an element or a braced group (fan-out / fan-in).
pub enum Endpoint {
    /// A single element.
    One(Port),
    /// `{ a, b, c }`
    Group(Vec<Port>),
}

impl Endpoint {
    /// The ports on this side, in order.
    pub fn ports(&self) -> &[Port] {
        match self {
            Endpoint::One(port) => core::slice::from_ref(port),
            Endpoint::Group(ports) => ports,
        }
    }
}

/// Where a bond attaches: an element, or one component of a splitter (`s.0`).
pub struct Port {
    /// The element.
    pub name: Ident,
    /// The component, for a splitter's scalar side.
    pub component: Option<syn::LitInt>,
}

fn parse_port(input: ParseStream, recovered: &mut Recovered) -> syn::Result<Port> {
    let name = name(input, recovered)?;
    let component = if input.peek(Token![.]) && input.peek2(syn::LitInt) {
        input.parse::<Token![.]>()?;
        Some(input.parse()?)
    } else {
        None
    };
    Ok(Port { name, component })
}

/// `->` or `-[label]->`: a bond's half arrow, power flowing left to right.
pub struct Arrow {
    /// The bond's label, if given.
    pub label: Option<Ident>,
    /// Where the arrow is written.
    pub span: Span,
}

/// `init element.var = expr;`
pub struct InitDecl {
    /// The storage element.
    pub element: Ident,
    /// Its state variable (`q` or `p`).
    pub var: Ident,
    /// The initial value, an expression in parameters.
    pub value: Expr,
}

/// `output name = expr;`
pub struct OutputDecl {
    /// Doc comments and other attributes.
    pub attrs: Vec<Attribute>,
    /// The output's name.
    pub name: Ident,
    /// Its shape, if declared (a vector output gives one column per component).
    pub shape: Option<Shape>,
    /// The expression, in signals, parameters and `t`.
    pub expr: Expr,
    /// Its unit, written `in "m"` after the expression.
    pub unit: Option<syn::LitStr>,
}

impl Parse for File {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let mut raw_models = Vec::new();
        let mut submodels: Vec<crate::flatten::SubmodelDef> = Vec::new();
        while !input.is_empty() {
            let attrs = input.call(Attribute::parse_outer)?;
            let vis: Visibility = input.parse()?;
            let lookahead = input.lookahead1();
            if lookahead.peek(kw::submodel) {
                input.parse::<kw::submodel>()?;
                submodels.push(input.parse()?);
            } else if lookahead.peek(kw::model) {
                input.parse::<kw::model>()?;
                let name: Ident = input.parse()?;
                let body;
                let brace = braced!(body in input);
                let body: proc_macro2::TokenStream = body.parse()?;
                raw_models.push((attrs, vis, name, body, brace.span.close()));
            } else {
                return Err(lookahead.error());
            }
        }
        if raw_models.is_empty() {
            return Err(syn::Error::new(
                Span::call_site(),
                "expected a model: `pub model Name { ... }`",
            ));
        }
        // The model's own submodels first: they shadow the standard library's.
        let library = crate::stdlib::submodels()?;
        let visible: Vec<&crate::flatten::SubmodelDef> = submodels.iter().chain(&library).collect();
        let mut models = Vec::new();
        for (attrs, vis, name, body, close) in raw_models {
            let mut errors = Vec::new();
            let mut placed = Vec::new();
            let flat = crate::flatten::flatten(body, &visible, &mut errors, &mut placed);
            // Only the library's own RigidBody has the states an animation reads.
            let bodies = placed
                .into_iter()
                .filter(|p| {
                    p.submodel >= submodels.len()
                        && visible[p.submodel].name == crate::stdlib::RIGID_BODY
                })
                .map(|p| p.path)
                .collect();
            let mut keywords_in_paths = Vec::new();
            let declared = keywords_declared(&flat);
            let flat = raw_keyword_paths(flat, &declared, &mut keywords_in_paths);
            // Braces around the flat body, so "expected `;`" at its end still points
            // at the model's closing brace.
            let mut group = proc_macro2::Group::new(proc_macro2::Delimiter::Brace, flat);
            group.set_span(close);
            let in_braces = |input: ParseStream| {
                let body;
                braced!(body in input);
                parse_body(&body, &keywords_in_paths)
            };
            let tokens = proc_macro2::TokenTree::Group(group).into();
            let (stmts, parse_errors, poisoned) = syn::parse::Parser::parse2(in_braces, tokens)?;
            errors.extend(parse_errors);
            models.push(ModelDef {
                attrs,
                vis,
                name,
                stmts,
                errors,
                poisoned,
                bodies,
            });
        }
        Ok(File { models })
    }
}

/// Mistakes the parser steps over without losing the statement.
#[derive(Default)]
struct Recovered {
    /// Errors reported as they are found.
    errors: Vec<syn::Error>,
    /// Keywords written as names (taken as raw identifiers), reported once per word.
    keywords: Vec<(String, Span)>,
}

/// A model's (flattened) statements, recovering after each one that does not parse.
/// `keywords_in_paths` are keywords the body uses as names in `loop.f` (see
/// [`raw_keyword_paths`]).
fn parse_body(
    body: ParseStream,
    keywords_in_paths: &[(String, Span)],
) -> syn::Result<(Vec<Stmt>, Vec<syn::Error>, Vec<Ident>)> {
    let mut stmts = Vec::new();
    let mut recovered = Recovered::default();
    let mut poisoned = Vec::new();
    while !body.is_empty() {
        let start = body.fork();
        let start_cursor = body.cursor();
        let parsed = parse_stmt(body, &mut recovered).and_then(|stmt| {
            if matches!(stmt, Stmt::When(_)) {
                // A `when` ends with its braces; a `;` after them is allowed.
                if body.peek(Token![;]) {
                    body.parse::<Token![;]>()?;
                }
            } else if !body.peek(Token![;]) && !body.is_empty() && starts_statement(body) {
                // Only the `;` is missing: say so where it belongs and read on from the
                // next statement, which is intact.
                recovered
                    .errors
                    .push(missing_semicolon(start_cursor, body.cursor()));
            } else {
                body.parse::<Token![;]>()?;
            }
            Ok(stmt)
        });
        match parsed {
            Ok(stmt) => stmts.push(stmt),
            Err(error) => {
                recovered.errors.push(error);
                // Before `declared_name`, which reads on from `start`.
                let when = is_when(&start);
                poisoned.extend(declared_name(&start));
                if when {
                    skip_past_braces(body, start_cursor);
                } else {
                    skip_past_semicolon(body);
                }
            }
        }
    }
    let mut errors = recovered.errors;
    let mut reported = std::collections::BTreeSet::new();
    for (word, span) in recovered.keywords.iter().chain(keywords_in_paths) {
        if reported.insert(word.clone()) {
            errors.push(crate::keywords::keyword_error(word, *span));
        }
    }
    Ok((stmts, errors, poisoned))
}

/// "expected `;` after `1.0`", at the statement's last token.
fn missing_semicolon(start: syn::buffer::Cursor, end: syn::buffer::Cursor) -> syn::Error {
    let mut last = None;
    let mut cursor = start;
    while cursor != end {
        let Some((tt, next)) = cursor.token_tree() else {
            break;
        };
        last = Some(tt);
        cursor = next;
    }
    let Some(last) = last else {
        return syn::Error::new(end.span(), "expected `;`");
    };
    let text = match &last {
        TokenTree::Group(_) => String::new(),
        tt => format!(" after `{tt}`"),
    };
    syn::Error::new(
        last.span(),
        format!("expected `;`{text}: every statement ends with `;`"),
    )
}

/// Whether the input starts a new statement: a doc comment or attribute, a
/// statement keyword before a name, an element kind before a name or `[n]`, or a bond.
fn starts_statement(input: ParseStream) -> bool {
    let named = |fork: ParseStream| fork.peek(Ident::peek_any);
    if input.peek(Token![#]) {
        return true;
    }
    if input.peek(LitInt) {
        return input.peek2(Ident::peek_any) || input.peek2(syn::token::Bracket);
    }
    if input.peek(syn::token::Brace) {
        return input.peek2(Token![->]) || input.peek2(Token![-]);
    }
    let fork = input.fork();
    let Ok(word) = Ident::parse_any(&fork) else {
        return false;
    };
    let text = word.to_string();
    if text == "when" && !fork.peek(Token![->]) && !fork.peek(Token![-]) {
        return true;
    }
    let statement_word =
        ["param", "input", "state", "der", "init", "output", "mode"].contains(&text.as_str());
    let element_word = ElementKind::from_word(&text).is_some();
    ((statement_word || element_word) && named(&fork))
        || (element_word && fork.peek(syn::token::Bracket))
        || fork.peek(Token![->])
        || (fork.peek(Token![-]) && fork.peek2(syn::token::Bracket))
}

/// Keywords a statement declares as names, written plainly: `1 loop;`, `param type =
/// ...;`, `C[3] match = ...;` (the parser reports each; [`raw_keyword_paths`] reads the
/// other uses of the word as that name).
fn keywords_declared(tokens: &TokenStream) -> Vec<String> {
    let trees: Vec<TokenTree> = tokens.clone().into_iter().collect();
    let mut declared = Vec::new();
    for (i, tt) in trees.iter().enumerate() {
        let introduces = match tt {
            TokenTree::Ident(word) => {
                let word = word.to_string();
                ["param", "input", "state", "output", "der", "mode"].contains(&word.as_str())
                    || ElementKind::from_word(&word).is_some()
            }
            TokenTree::Literal(lit) => ["0", "1"].contains(&lit.to_string().as_str()),
            _ => false,
        };
        if !introduces {
            continue;
        }
        let mut next = i + 1;
        if matches!(trees.get(next), Some(TokenTree::Group(g)) if g.delimiter() == proc_macro2::Delimiter::Bracket)
        {
            next += 1;
        }
        if let Some(TokenTree::Ident(name)) = trees.get(next) {
            let word = name.to_string();
            if crate::keywords::is_raw_able_keyword(&word) && !declared.contains(&word) {
                declared.push(word);
            }
        }
    }
    declared
}

/// Keywords used as names become raw identifiers, so the statements that use them
/// still parse; each use is noted for one error per word. A keyword is taken as a name
/// before a `.` (`loop.f`, `init loop.q`: no keyword is followed by `.` in a valid
/// statement) and wherever a word in `declared` appears, but not where it is declared
/// (the parser reports that) nor before a string (`in "unit"`).
fn raw_keyword_paths(
    tokens: TokenStream,
    declared: &[String],
    found: &mut Vec<(String, Span)>,
) -> TokenStream {
    let trees: Vec<TokenTree> = tokens.into_iter().collect();
    let mut out = TokenStream::new();
    for (i, tt) in trees.iter().enumerate() {
        match tt {
            TokenTree::Ident(ident) => {
                let word = ident.to_string();
                let before_dot = matches!(
                    (trees.get(i + 1), trees.get(i + 2)),
                    (Some(TokenTree::Punct(dot)), Some(TokenTree::Ident(_) | TokenTree::Literal(_)))
                        if dot.as_char() == '.' && dot.spacing() == proc_macro2::Spacing::Alone
                );
                let declaration = i > 0
                    && !before_dot
                    && keywords_declared(&trees[i.saturating_sub(2)..=i].iter().cloned().collect())
                        .contains(&word);
                let before_string = matches!(trees.get(i + 1), Some(TokenTree::Literal(lit)) if lit.to_string().starts_with('"'));
                let declared_name = declared.contains(&word) && !declaration && !before_string;
                if (before_dot || declared_name) && crate::keywords::is_raw_able_keyword(&word) {
                    found.push((word.clone(), ident.span()));
                    out.extend([TokenTree::Ident(Ident::new_raw(&word, ident.span()))]);
                } else {
                    out.extend([tt.clone()]);
                }
            }
            TokenTree::Group(group) => {
                let mut copy = proc_macro2::Group::new(
                    group.delimiter(),
                    raw_keyword_paths(group.stream(), declared, found),
                );
                copy.set_span(group.span());
                out.extend([TokenTree::Group(copy)]);
            }
            _ => out.extend([tt.clone()]),
        }
    }
    out
}

/// A name: an identifier, or a keyword written where a name belongs, which is taken as
/// the raw identifier it should have been (`loop` as `r#loop`) and noted for one error,
/// so that nothing else fails because of it.
fn name(input: ParseStream, recovered: &mut Recovered) -> syn::Result<Ident> {
    if !input.peek(Ident) && input.peek(Ident::peek_any) {
        let word = input.fork().call(Ident::parse_any)?.to_string();
        if crate::keywords::is_raw_able_keyword(&word) {
            let keyword = input.call(Ident::parse_any)?;
            recovered.keywords.push((word.clone(), keyword.span()));
            return Ok(Ident::new_raw(&word, keyword.span()));
        }
    }
    input.parse()
}

/// The name a statement declares, read without parsing it: `KIND name ...`,
/// `param name ...` or `output name ...`.
fn declared_name(input: ParseStream) -> Option<Ident> {
    let _ = input.call(Attribute::parse_outer);
    let declares = input.peek(Ident) || input.peek(LitInt);
    if declares && input.peek2(Ident::peek_any) {
        let _ = input.parse::<proc_macro2::TokenTree>();
        let word = input.call(Ident::parse_any).ok()?;
        let text = word.to_string();
        Some(if crate::keywords::is_raw_able_keyword(&text) {
            Ident::new_raw(&text, word.span())
        } else {
            word
        })
    } else {
        None
    }
}

/// Runs `parse` on the contents of a delimited group and, if it fails, consumes what
/// is left of the group: syn otherwise turns the leftover tokens into an "unexpected
/// token" error that replaces every other error of the invocation.
pub fn parse_group<T>(
    group: ParseStream,
    parse: impl FnOnce(ParseStream) -> syn::Result<T>,
) -> syn::Result<T> {
    let result = parse(group);
    if result.is_err() {
        let _ = group.step(|cursor| {
            let mut rest = *cursor;
            while let Some((_, next)) = rest.token_tree() {
                rest = next;
            }
            Ok(((), rest))
        });
    }
    result
}

/// Error recovery: drop tokens up to and including the next `;` at this level, so one
/// malformed statement does not hide mistakes in the following ones.
fn skip_past_semicolon(input: ParseStream) {
    let _ = input.step(|cursor| {
        let mut rest = *cursor;
        while let Some((tt, next)) = rest.token_tree() {
            rest = next;
            if let proc_macro2::TokenTree::Punct(p) = &tt {
                if p.as_char() == ';' {
                    break;
                }
            }
        }
        Ok(((), rest))
    });
}

/// Whether `input` (at a statement's start, attributes included) is a `when` block:
/// the word `when` not starting a bond (`when -> x`).
fn is_when(input: ParseStream) -> bool {
    let fork = input.fork();
    let _ = fork.call(Attribute::parse_outer);
    fork.peek(crate::event_syntax::kw::when)
        && !fork.peek2(Token![->])
        && !(fork.peek2(Token![-]) && fork.peek3(syn::token::Bracket))
}

/// Error recovery for a `when` that started at `start`: drop tokens up to and
/// including its braces (the first brace group after `start`), unless the parser has
/// read past them already.
fn skip_past_braces(input: ParseStream, start: syn::buffer::Cursor) {
    let is_brace = |tt: &TokenTree| matches!(tt, TokenTree::Group(g) if g.delimiter() == proc_macro2::Delimiter::Brace);
    let mut length = 0;
    let mut cursor = start;
    while let Some((tt, next)) = cursor.token_tree() {
        length += 1;
        cursor = next;
        if is_brace(&tt) {
            break;
        }
    }
    let _ = input.step(|now| {
        let mut read = 0;
        let mut cursor = start;
        while cursor != *now {
            let Some((_, next)) = cursor.token_tree() else {
                break;
            };
            read += 1;
            cursor = next;
        }
        let mut rest = *now;
        for _ in read..length {
            match rest.token_tree() {
                Some((_, next)) => rest = next,
                None => break,
            }
        }
        Ok(((), rest))
    });
}

/// One statement, without its `;`.
fn parse_stmt(input: ParseStream, recovered: &mut Recovered) -> syn::Result<Stmt> {
    if is_when(input) {
        let attrs = input.call(Attribute::parse_outer)?;
        return crate::event_syntax::parse_when(input, attrs).map(Stmt::When);
    }
    let attrs = input.call(Attribute::parse_outer)?;
    if input.peek(crate::event_syntax::kw::mode) && input.peek2(Ident::peek_any) {
        return crate::event_syntax::parse_mode(input, attrs).map(Stmt::Mode);
    }
    let lookahead = input.lookahead1();
    let stmt = if lookahead.peek(kw::param) || lookahead.peek(kw::input) {
        let is_input = input.peek(kw::input);
        if is_input {
            input.parse::<kw::input>()?;
        } else {
            input.parse::<kw::param>()?;
        }
        let name = name(input, recovered)?;
        let shape = optional_shape(input)?.unwrap_or(Shape::Scalar);
        input.parse::<Token![=]>()?;
        let default = input.parse()?;
        let unit = optional_unit(input)?;
        Stmt::Param(ParamDecl {
            attrs,
            name,
            shape,
            default,
            unit,
            input: is_input,
        })
    } else if lookahead.peek(kw::state) {
        input.parse::<kw::state>()?;
        let name = name(input, recovered)?;
        input.parse::<Token![:]>()?;
        let shape = parse_shape(input)?;
        input.parse::<Token![=]>()?;
        let init = input.parse()?;
        let unit = optional_unit(input)?;
        Stmt::State(StateDecl {
            attrs,
            name,
            shape,
            init,
            unit,
        })
    } else if lookahead.peek(kw::der) {
        no_attrs(&attrs, "a `der` statement")?;
        input.parse::<kw::der>()?;
        let name = name(input, recovered)?;
        input.parse::<Token![=]>()?;
        let expr = input.parse()?;
        Stmt::Der(DerDecl { name, expr })
    } else if lookahead.peek(kw::init) {
        no_attrs(&attrs, "an `init` statement")?;
        input.parse::<kw::init>()?;
        let element = name(input, recovered)?;
        input.parse::<Token![.]>()?;
        let var = input.parse()?;
        input.parse::<Token![=]>()?;
        let value = input.parse()?;
        Stmt::Init(InitDecl {
            element,
            var,
            value,
        })
    } else if lookahead.peek(kw::output) {
        input.parse::<kw::output>()?;
        let name = name(input, recovered)?;
        let shape = optional_shape(input)?;
        input.parse::<Token![=]>()?;
        let expr = input.parse()?;
        let unit = optional_unit(input)?;
        Stmt::Output(OutputDecl {
            attrs,
            name,
            shape,
            expr,
            unit,
        })
    } else if lookahead.peek(LitInt) {
        Stmt::Element(parse_junction(input, attrs, recovered)?)
    } else if lookahead.peek(Ident) {
        if input.peek2(Ident::peek_any) || input.peek2(syn::token::Bracket) {
            Stmt::Element(parse_element(input, attrs, recovered)?)
        } else {
            Stmt::Bonds(parse_chain(input, attrs, recovered)?)
        }
    } else if lookahead.peek(syn::token::Brace) {
        Stmt::Bonds(parse_chain(input, attrs, recovered)?)
    } else if input.peek(Ident::peek_any) && input.peek2(Token![-]) {
        // A bond from an element named by a keyword: `loop -> v`.
        Stmt::Bonds(parse_chain(input, attrs, recovered)?)
    } else {
        return Err(lookahead.error());
    };
    Ok(stmt)
}

/// `in "unit"` after a value, if written.
fn optional_unit(input: ParseStream) -> syn::Result<Option<syn::LitStr>> {
    if input.peek(Token![in]) {
        input.parse::<Token![in]>()?;
        Ok(Some(input.parse()?))
    } else {
        Ok(None)
    }
}

fn no_attrs(attrs: &[Attribute], what: &str) -> syn::Result<()> {
    match attrs.first() {
        Some(attr) => Err(syn::Error::new_spanned(
            attr,
            format!("attributes and doc comments are not allowed on {what}"),
        )),
        None => Ok(()),
    }
}

fn parse_junction(
    input: ParseStream,
    attrs: Vec<Attribute>,
    recovered: &mut Recovered,
) -> syn::Result<ElementDecl> {
    let lit: LitInt = input.parse()?;
    let kind = match lit.base10_digits() {
        "0" if lit.suffix().is_empty() => ElementKind::Zero,
        "1" if lit.suffix().is_empty() => ElementKind::One,
        _ => {
            return Err(syn::Error::new(
                lit.span(),
                format!(
                    "unknown element kind `{lit}`: expected one of {ELEMENT_KINDS} \
                     (junctions are written `0 name;` and `1 name;`)"
                ),
            ))
        }
    };
    let dimension = optional_dimension(input)?;
    let name = name(input, recovered)?;
    if input.peek(Token![=]) || input.peek(syn::token::Brace) {
        // A mistake the parser can step over: report it, skip the law, keep the junction.
        recovered.errors.push(input.error(format!(
            "a {} has no constitutive law: write `{} {};`",
            kind.describe(),
            kind.word(),
            name
        )));
        let _ = input.step(|cursor| {
            let mut rest = *cursor;
            while let Some((tt, next)) = rest.token_tree() {
                if matches!(&tt, proc_macro2::TokenTree::Punct(p) if p.as_char() == ';') {
                    break;
                }
                rest = next;
            }
            Ok(((), rest))
        });
    }
    Ok(ElementDecl {
        attrs,
        kind,
        modulated: false,
        dimension,
        name,
        law: LawSyntax::None,
        inverse: None,
        state_unit: None,
    })
}

fn parse_element(
    input: ParseStream,
    attrs: Vec<Attribute>,
    recovered: &mut Recovered,
) -> syn::Result<ElementDecl> {
    let word: Ident = input.parse()?;
    let Some(kind) = ElementKind::from_word(&word.to_string()) else {
        return Err(syn::Error::new(
            word.span(),
            format!(
                "unknown element kind `{word}`: expected one of {ELEMENT_KINDS}, \
                 or a statement (`param`, `state`, `der`, `init`, `output`, or a bond `a -> b`)"
            ),
        ));
    };
    let dimension = optional_dimension(input)?;
    let name = name(input, recovered)?;
    let mut inverse = None;
    let law = if input.peek(Token![=]) {
        input.parse::<Token![=]>()?;
        let law = LawSyntax::Linear(Expr::parse_without_eager_brace(input)?);
        if matches!(kind, ElementKind::Tf | ElementKind::Gy) && input.peek(Token![,]) {
            input.parse::<Token![,]>()?;
            input.parse::<kw::inverse>()?;
            input.parse::<Token![=]>()?;
            inverse = Some(input.parse()?);
        }
        law
    } else if input.peek(syn::token::Brace) {
        let body;
        braced!(body in input);
        let forms = parse_group(&body, |body| {
            let mut forms = Vec::new();
            while !body.is_empty() {
                let var: Ident = body.parse()?;
                body.parse::<Token![=]>()?;
                let expr: Expr = body.parse()?;
                forms.push(LawForm { var, expr });
                if body.is_empty() {
                    break;
                }
                body.parse::<Token![,]>()?;
            }
            Ok(forms)
        })?;
        if forms.is_empty() {
            return Err(syn::Error::new(
                name.span(),
                format!("`{name}` has an empty law: write `{word} {name} = value;` or `{word} {name} {{ e = ... }};`"),
            ));
        }
        LawSyntax::Forms(forms)
    } else {
        LawSyntax::None
    };
    let state_unit = if input.peek(Token![,]) && !matches!(law, LawSyntax::None) {
        input.parse::<Token![,]>()?;
        let var: Ident = input.parse()?;
        if !input.peek(Token![in]) {
            return Err(input.error(format!(
                "expected `in \"unit\"`: a storage element's state takes a unit, \
                 `{word} {name} = ..., {var} in \"m\";`"
            )));
        }
        input.parse::<Token![in]>()?;
        Some((var, input.parse()?))
    } else {
        None
    };
    Ok(ElementDecl {
        attrs,
        kind,
        modulated: word.to_string().starts_with('M'),
        dimension,
        name,
        law,
        inverse,
        state_unit,
    })
}

/// `a -> b -[label]-> { c, d }`, up to (not including) its `;`.
fn parse_chain(
    input: ParseStream,
    attrs: Vec<Attribute>,
    recovered: &mut Recovered,
) -> syn::Result<BondChain> {
    let first = parse_endpoint(input, recovered)?;
    let mut links = Vec::new();
    loop {
        let lookahead = input.lookahead1();
        if lookahead.peek(Token![->]) {
            let arrow: Token![->] = input.parse()?;
            let arrow = Arrow {
                label: None,
                span: arrow.span(),
            };
            links.push((arrow, parse_endpoint(input, recovered)?));
        } else if lookahead.peek(Token![-]) {
            let dash: Token![-] = input.parse()?;
            let inner;
            bracketed!(inner in input);
            let label = parse_group(&inner, |inner| {
                let label = name(inner, recovered)?;
                if !inner.is_empty() {
                    return Err(inner.error("expected `]`: a bond label is one name, `-[b1]->`"));
                }
                Ok(label)
            })?;
            input.parse::<Token![->]>()?;
            let arrow = Arrow {
                label: Some(label),
                span: dash.span(),
            };
            links.push((arrow, parse_endpoint(input, recovered)?));
        } else if !links.is_empty() && (lookahead.peek(Token![;]) || starts_statement(input)) {
            // The `;`, or the next statement where it is missing (reported by the caller).
            break;
        } else if input.peek(Token![<-]) {
            return Err(input.error(
                "bonds point the way power flows, left to right: write `b -> a` instead of `a <- b`",
            ));
        } else if input.peek(Token![=>]) {
            return Err(input.error("a bond's half arrow is written `->`, not `=>`"));
        } else {
            return Err(lookahead.error());
        }
    }
    Ok(BondChain {
        attrs,
        first,
        links,
    })
}

/// One side of an arrow: a name, a splitter component, or a braced group.
fn parse_endpoint(input: ParseStream, recovered: &mut Recovered) -> syn::Result<Endpoint> {
    let lookahead = input.lookahead1();
    if lookahead.peek(Ident) || input.peek(Ident::peek_any) {
        Ok(Endpoint::One(parse_port(input, recovered)?))
    } else if lookahead.peek(syn::token::Brace) {
        let body;
        let brace = braced!(body in input);
        let ports = parse_group(&body, |body| {
            let mut ports = Vec::new();
            while !body.is_empty() {
                ports.push(parse_port(body, recovered)?);
                if body.is_empty() {
                    break;
                }
                body.parse::<Token![,]>()?;
            }
            Ok(ports)
        })?;
        if ports.is_empty() {
            return Err(syn::Error::new(
                brace.span.join(),
                "an empty group `{}` connects nothing: name at least one element",
            ));
        }
        Ok(Endpoint::Group(ports))
    } else {
        Err(lookahead.error())
    }
}

#[cfg(test)]
mod should {
    use super::*;

    fn parse(text: &str) -> syn::Result<File> {
        syn::parse_str(text)
    }

    #[test]
    fn parse_the_design_sketch() {
        let file = parse(
            "/// doc
             pub model Oscillator {
                 /// mass, kg
                 param m = 1.0;
                 Se push = force;
                 I mass = m;
                 R damper { e = c * f * f.abs() };
                 1 v;
                 push -> v -> { mass, damper };
                 init mass.p = 0.5;
                 output speed = v.f;
             }",
        )
        .unwrap();
        let model = &file.models[0];
        assert_eq!(model.name, "Oscillator");
        assert!(model.errors.is_empty());
        assert_eq!(model.stmts.len(), 8);
        let Stmt::Bonds(chain) = &model.stmts[5] else {
            panic!("expected bonds")
        };
        assert_eq!(chain.links.len(), 2);
        assert_eq!(chain.links[1].1.ports().len(), 2);
    }

    #[test]
    fn read_units_of_outputs_states_and_storage() {
        let file = parse(
            r#"model M {
                 C spring = k, q in "m";
                 I[3] body { f = p / m }, p in "kg·m/s";
                 state r: Vector3 = r0 in "m";
                 output x = spring.q in "m";
                 output F: Vector3 = body.e in "N";
             }"#,
        )
        .unwrap();
        let model = &file.models[0];
        assert!(model.errors.is_empty());
        let units: Vec<String> = model
            .stmts
            .iter()
            .map(|stmt| match stmt {
                Stmt::Element(e) => e.state_unit.as_ref().unwrap().1.value(),
                Stmt::State(s) => s.unit.as_ref().unwrap().value(),
                Stmt::Output(o) => o.unit.as_ref().unwrap().value(),
                _ => panic!("unexpected statement"),
            })
            .collect();
        assert_eq!(units, ["m", "kg·m/s", "m", "m", "N"]);
    }

    #[test]
    fn reject_a_state_unit_without_in() {
        let file = parse(r#"model M { C spring = k, q "m"; }"#).unwrap();
        let message = file.models[0].errors[0].to_string();
        assert!(message.contains("expected `in \"unit\"`"), "{message}");
    }

    #[test]
    fn read_a_labelled_arrow() {
        let file = parse("model M { a -[b7]-> c; }").unwrap();
        let Stmt::Bonds(chain) = &file.models[0].stmts[0] else {
            panic!("expected bonds")
        };
        assert_eq!(chain.links[0].0.label.as_ref().unwrap(), "b7");
    }

    #[test]
    fn read_junction_kinds_from_digits() {
        let file = parse("model M { 0 a; 1 b; }").unwrap();
        let kinds: Vec<_> = file.models[0]
            .stmts
            .iter()
            .map(|s| match s {
                Stmt::Element(e) => e.kind,
                _ => panic!("expected elements"),
            })
            .collect();
        assert_eq!(kinds, [ElementKind::Zero, ElementKind::One]);
    }

    #[test]
    fn recover_after_a_bad_statement_and_report_each() {
        let file = parse("model M { Q x = 1.0; C c = 1.0; 2 j; a -> ; }").unwrap();
        let model = &file.models[0];
        assert_eq!(model.stmts.len(), 1, "the C element still parses");
        let messages: Vec<String> = model.errors.iter().map(|e| e.to_string()).collect();
        assert_eq!(messages.len(), 3, "{messages:?}");
        assert!(messages[0].starts_with("unknown element kind `Q`"));
        assert!(messages[1].starts_with("unknown element kind `2`"));
        assert!(messages[2].starts_with("expected"));
        // Names the failed declarations meant, so references to them stay quiet.
        let poisoned: Vec<String> = model.poisoned.iter().map(|n| n.to_string()).collect();
        assert_eq!(poisoned, ["x", "j"]);
    }

    #[test]
    fn keep_other_errors_when_a_braced_law_is_malformed() {
        let file =
            parse("model M { C spring { e = 100.0 * q g }; Q x = 1.0; a -[b1 b2]-> c; }").unwrap();
        let messages: Vec<String> = file.models[0]
            .errors
            .iter()
            .map(|e| e.to_string())
            .collect();
        assert_eq!(messages.len(), 3, "{messages:?}");
        assert!(messages[1].starts_with("unknown element kind `Q`"));
        assert!(messages[2].starts_with("expected `]`: a bond label is one name"));
    }

    #[test]
    fn list_each_expected_token_once() {
        let file = parse("model M { * x; }").unwrap();
        let message = file.models[0].errors[0].to_string();
        assert_eq!(message.matches("identifier").count(), 1, "{message}");
    }

    #[test]
    fn take_a_keyword_name_as_raw_and_report_it_once() {
        let file = parse(
            "model M { Se push = 1.0; 1 loop; push -> loop; loop -[type]-> push;
                       output v = loop.f; init loop.q = 0.0; }",
        )
        .unwrap();
        let model = &file.models[0];
        let messages: Vec<String> = model.errors.iter().map(|e| e.to_string()).collect();
        assert_eq!(messages.len(), 2, "{messages:?}");
        assert!(
            messages[0].starts_with("`loop` is a Rust keyword"),
            "{messages:?}"
        );
        assert!(messages[0].contains("help: write `r#loop`"), "{messages:?}");
        assert!(
            messages[1].starts_with("`type` is a Rust keyword"),
            "{messages:?}"
        );
        assert_eq!(model.stmts.len(), 6, "every statement still parses");
        let Stmt::Element(junction) = &model.stmts[1] else {
            panic!("expected the junction")
        };
        assert_eq!(junction.name.to_string(), "r#loop");
    }

    #[test]
    fn read_a_plainly_declared_keyword_as_that_name_in_expressions() {
        let file = parse(
            r#"model M { param type = 2.0 in "kg"; Se s = 3.0 * type; I m = type, p in "kg·m/s";
                         s -> m; output w = type; }"#,
        )
        .unwrap();
        let model = &file.models[0];
        let messages: Vec<String> = model.errors.iter().map(|e| e.to_string()).collect();
        assert_eq!(messages.len(), 1, "{messages:?}");
        assert!(messages[0].starts_with("`type` is a Rust keyword"));
        assert_eq!(model.stmts.len(), 5);
    }

    #[test]
    fn accept_raw_names_without_a_word() {
        let file =
            parse("model M { Se r#in = 1.0; 1 r#loop; r#in -> r#loop; output v = r#loop.f; }")
                .unwrap();
        assert!(file.models[0].errors.is_empty());
        assert_eq!(file.models[0].stmts.len(), 4);
    }

    #[test]
    fn report_a_missing_semicolon_once_and_read_on() {
        let file =
            parse("model M { Sf push = 1.0 C spring = 100.0; push -> spring 1 v; }").unwrap();
        let model = &file.models[0];
        let messages: Vec<String> = model.errors.iter().map(|e| e.to_string()).collect();
        assert_eq!(
            messages,
            [
                "expected `;` after `1.0`: every statement ends with `;`",
                "expected `;` after `spring`: every statement ends with `;`"
            ]
        );
        assert_eq!(model.stmts.len(), 4, "no statement is lost");
        assert!(model.poisoned.is_empty());
    }

    #[test]
    fn skip_a_statement_whose_end_is_garbled() {
        let file = parse("model M { output y = a b c; C spring = 1.0; }").unwrap();
        let model = &file.models[0];
        assert_eq!(model.errors.len(), 1, "{:?}", model.errors[0].to_string());
        assert_eq!(model.stmts.len(), 1);
    }

    #[test]
    fn reject_a_law_on_a_junction_but_keep_the_junction() {
        let file = parse("model M { 1 v = 3.0; }").unwrap();
        assert_eq!(file.models[0].stmts.len(), 1);
        assert!(file.models[0].errors[0]
            .to_string()
            .contains("has no constitutive law"));
    }
}
