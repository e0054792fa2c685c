//! Stage 1b: submodels. A submodel is a fragment of a model with parameters; each
//! instance `Name inst(arg = expr, ...);` is inlined into the model before anything is
//! resolved, at the level of tokens:
//!
//! - names the submodel declares (elements, junctions, states, labels, outputs, nested
//!   instances) are prefixed with the instance's name, `inst__name`, and shown to the
//!   user as `inst.name`;
//! - its parameters are replaced by the argument expressions (in parentheses, unless
//!   the argument is a plain name, so an instance can be passed as `body = crank`);
//! - every token of the body takes the instantiation's span, so an error inside an
//!   instance points at the user's text, and the message names the part (`crank.v`);
//! - finally `inst.name` written anywhere in the model becomes `inst__name`.
//!
//! After this stage a model is flat and the rest of the pipeline knows nothing of
//! submodels.

use std::collections::{BTreeMap, BTreeSet};

use proc_macro2::{Delimiter, Group, Ident, Span, TokenStream, TokenTree};
use syn::ext::IdentExt;
use syn::parse::{Parse, ParseStream};
use syn::{braced, parenthesized, Token};

/// The separator between an instance's name and a name inside it.
pub const SEPARATOR: &str = "__";

/// How a (possibly prefixed) name is shown to the user: `crank__v` as `crank.v`.
pub fn display(name: &str) -> String {
    crate::keywords::unraw(&name.replace(SEPARATOR, "."))
}

/// `instance__name` for a part of an instance (a raw `r#loop` loses its prefix there:
/// `crank__loop` is a plain name).
fn prefixed(instance: &Ident, name: &Ident, span: Span) -> Ident {
    let (instance, name) = (instance.unraw(), name.unraw());
    Ident::new(&format!("{instance}{SEPARATOR}{name}"), span)
}

/// A copy of `ident` at `span`, raw if it was.
fn respanned(ident: &Ident, span: Span) -> Ident {
    let mut copy = ident.clone();
    copy.set_span(span);
    copy
}

/// `submodel Name(param, param = default, ...) { statements }`
pub struct SubmodelDef {
    /// The submodel's name.
    pub name: Ident,
    /// Its parameters, in order, with their defaults.
    pub params: Vec<(Ident, Option<TokenStream>)>,
    /// The statements, as tokens.
    pub body: TokenStream,
}

impl Parse for SubmodelDef {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name: Ident = input.parse()?;
        let list;
        parenthesized!(list in input);
        let mut params = Vec::new();
        while !list.is_empty() {
            let param: Ident = list.parse()?;
            // A type annotation documents the parameter; arguments are substituted.
            if list.peek(Token![:]) {
                list.parse::<Token![:]>()?;
                list.parse::<syn::Type>()?;
            }
            let default = if list.peek(Token![=]) {
                list.parse::<Token![=]>()?;
                let expr: syn::Expr = list.parse()?;
                Some(quote::ToTokens::to_token_stream(&expr))
            } else {
                None
            };
            params.push((param, default));
            if list.is_empty() {
                break;
            }
            list.parse::<Token![,]>()?;
        }
        let body;
        braced!(body in input);
        Ok(SubmodelDef {
            name,
            params,
            body: body.parse()?,
        })
    }
}

/// How deep instances may nest: deeper means a submodel instantiates itself.
const MAX_DEPTH: usize = 16;

/// One instance inlined: its path (`arm__upper` for `upper` inside `arm`) and the index
/// in `submodels` of the definition it instantiates.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Placed {
    /// The instance's flat name.
    pub path: String,
    /// Which of the visible submodels it is.
    pub submodel: usize,
}

/// Inlines every instance in `body`, returning flat statements; mistakes go to `errors`,
/// every instance inlined (nested ones too, in the order inlined) to `placed`.
pub fn flatten(
    body: TokenStream,
    submodels: &[&SubmodelDef],
    errors: &mut Vec<syn::Error>,
    placed: &mut Vec<Placed>,
) -> TokenStream {
    let body = label_whens(body);
    // The separator is reserved for the names instances give their parts.
    let own = declared_idents(&body);
    let library = submodels.iter().flat_map(|d| declared_idents(&d.body));
    for name in own
        .into_iter()
        .chain(library)
        .filter(|n| n.to_string().contains(SEPARATOR))
    {
        errors.push(syn::Error::new(
            name.span(),
            format!(
                "`{name}`: names may not contain `{SEPARATOR}`, which is reserved for the \
                 parts of submodel instances\n\
                 help: rename it without `{SEPARATOR}`, e.g. `{}`",
                name.to_string().replace(SEPARATOR, "_")
            ),
        ));
    }
    let mut instances = BTreeSet::new();
    let flat = expand(body, submodels, errors, &mut instances, placed, 0);
    merge_paths(flat, &instances)
}

fn expand(
    body: TokenStream,
    submodels: &[&SubmodelDef],
    errors: &mut Vec<syn::Error>,
    instances: &mut BTreeSet<String>,
    placed: &mut Vec<Placed>,
    depth: usize,
) -> TokenStream {
    let mut out = TokenStream::new();
    for statement in statements(body) {
        let Some((submodel, name, args)) = instance(&statement) else {
            out.extend(statement);
            continue;
        };
        let Some((index, def)) = submodels
            .iter()
            .enumerate()
            .find(|(_, d)| d.name == submodel)
        else {
            let known: Vec<String> = submodels.iter().map(|d| d.name.to_string()).collect();
            errors.push(syn::Error::new(
                submodel.span(),
                format!(
                    "unknown submodel `{submodel}`; the submodels are: {}",
                    known.join(", ")
                ),
            ));
            continue;
        };
        if depth >= MAX_DEPTH {
            errors.push(syn::Error::new(
                name.span(),
                format!(
                    "submodel `{submodel}` instantiates itself (nesting deeper than {MAX_DEPTH})\n\
                     help: a submodel cannot contain an instance of itself, directly or through \
                     the submodels it instantiates: remove the instance of `{submodel}` from its \
                     own body, or of the submodel that leads back to it"
                ),
            ));
            continue;
        }
        let Some(substitutions) = arguments(def, &name, args, errors) else {
            continue;
        };
        instances.insert(name.to_string());
        placed.push(Placed {
            path: name.to_string(),
            submodel: index,
        });
        let def_body = label_whens(def.body.clone());
        let locals = declared_names(&def_body);
        let inlined = rewrite(def_body, &name, &locals, &substitutions);
        out.extend(expand(
            inlined,
            submodels,
            errors,
            instances,
            placed,
            depth + 1,
        ));
    }
    out
}

/// Splits a body into statements, each with its `;` (a `when` block ends with its
/// braces).
fn statements(body: TokenStream) -> Vec<Vec<TokenTree>> {
    let mut all = Vec::new();
    let mut current = Vec::new();
    for tt in body {
        let end = match &tt {
            TokenTree::Punct(p) => p.as_char() == ';',
            TokenTree::Group(g) => g.delimiter() == Delimiter::Brace && starts_when(&current),
            _ => false,
        };
        current.push(tt);
        if end {
            all.push(std::mem::take(&mut current));
        }
    }
    if !current.is_empty() {
        all.push(current);
    }
    all
}

/// Leading `#[...]` attributes (doc comments) of a statement, skipped.
fn skip_attributes(statement: &[TokenTree]) -> &[TokenTree] {
    let mut rest = statement;
    while let [TokenTree::Punct(hash), TokenTree::Group(group), tail @ ..] = rest {
        if hash.as_char() != '#' || group.delimiter() != Delimiter::Bracket {
            break;
        }
        rest = tail;
    }
    rest
}

/// Whether a statement (as far as it is read) is a `when` block: `when` first, not
/// starting a bond (`when -> x`, `when -[b]-> x`).
fn starts_when(statement: &[TokenTree]) -> bool {
    match skip_attributes(statement) {
        [TokenTree::Ident(word), rest @ ..] if word == "when" => !matches!(
            rest,
            [TokenTree::Punct(dash), TokenTree::Punct(_) | TokenTree::Group(_), ..]
                if dash.as_char() == '-'
                    && match &rest[1] {
                        TokenTree::Punct(arrow) => arrow.as_char() == '>',
                        TokenTree::Group(g) => g.delimiter() == Delimiter::Bracket,
                        _ => false,
                    }
        ),
        _ => false,
    }
}

/// Names every `when` of a body that has no label: `when_k` for the k-th `when` of the
/// body (1-based, labelled ones counted), written as a label after `when`, so that an
/// instance prefixes it like any name it declares (`stop.when_1`).
fn label_whens(body: TokenStream) -> TokenStream {
    let mut out = TokenStream::new();
    let mut k = 0;
    for statement in statements(body) {
        if !starts_when(&statement) {
            out.extend(statement);
            continue;
        }
        k += 1;
        let at = statement.len() - skip_attributes(&statement).len();
        let labelled = matches!(
            (statement.get(at + 1), statement.get(at + 2)),
            (Some(TokenTree::Ident(_)), Some(TokenTree::Punct(colon)))
                if colon.as_char() == ':' && colon.spacing() == proc_macro2::Spacing::Alone
        );
        if labelled {
            out.extend(statement);
            continue;
        }
        let span = statement[at].span();
        let mut statement = statement;
        statement.splice(
            at + 1..at + 1,
            [
                TokenTree::Ident(Ident::new(&format!("when_{k}"), span)),
                TokenTree::Punct(proc_macro2::Punct::new(':', proc_macro2::Spacing::Alone)),
            ],
        );
        out.extend(statement);
    }
    out
}

/// `Submodel name(args);`
fn instance(statement: &[TokenTree]) -> Option<(Ident, Ident, TokenStream)> {
    match skip_attributes(statement) {
        [TokenTree::Ident(submodel), TokenTree::Ident(name), TokenTree::Group(args), ..]
            if args.delimiter() == Delimiter::Parenthesis =>
        {
            Some((submodel.clone(), name.clone(), args.stream()))
        }
        _ => None,
    }
}

/// What each parameter is replaced by, or `None` after reporting a mistake.
fn arguments(
    def: &SubmodelDef,
    instance: &Ident,
    args: TokenStream,
    errors: &mut Vec<syn::Error>,
) -> Option<BTreeMap<String, TokenStream>> {
    struct Arg(Ident, syn::Expr);
    impl Parse for Arg {
        fn parse(input: ParseStream) -> syn::Result<Self> {
            let name = input.parse()?;
            input.parse::<Token![=]>()?;
            Ok(Arg(name, input.parse()?))
        }
    }
    let parser = syn::punctuated::Punctuated::<Arg, Token![,]>::parse_terminated;
    let parsed = match syn::parse::Parser::parse2(parser, args) {
        Ok(parsed) => parsed,
        Err(error) => {
            errors.push(error);
            return None;
        }
    };
    let mut given: BTreeMap<String, TokenStream> = BTreeMap::new();
    let mut ok = true;
    for Arg(name, expr) in parsed {
        if !def.params.iter().any(|(p, _)| *p == name) {
            let expected: Vec<String> = def.params.iter().map(|(p, _)| p.to_string()).collect();
            errors.push(syn::Error::new(
                name.span(),
                format!(
                    "submodel `{}` has no parameter `{name}`; its parameters are: {}",
                    def.name,
                    expected.join(", ")
                ),
            ));
            ok = false;
            continue;
        }
        // A plain name (an instance passed as `body = crank`) stays a name; anything
        // else is an expression and keeps its precedence.
        let tokens = match &expr {
            _ if is_name_path(&expr) => quote::ToTokens::to_token_stream(&expr),
            _ => TokenTree::Group(Group::new(
                Delimiter::Parenthesis,
                quote::ToTokens::to_token_stream(&expr),
            ))
            .into(),
        };
        given.insert(name.to_string(), tokens);
    }
    for (param, default) in &def.params {
        if given.contains_key(&param.to_string()) {
            continue;
        }
        match default {
            Some(default) => {
                let value = respan(default.clone(), instance.span());
                given.insert(
                    param.to_string(),
                    TokenTree::Group(Group::new(Delimiter::Parenthesis, value)).into(),
                );
            }
            None => {
                errors.push(syn::Error::new(
                    instance.span(),
                    format!("instance `{instance}` of `{}` needs the parameter `{param}`: add `{param} = ...`", def.name),
                ));
                ok = false;
            }
        }
    }
    ok.then_some(given)
}

/// `crank` or `crank.tip.v`: a name, passed on as written.
fn is_name_path(expr: &syn::Expr) -> bool {
    match expr {
        syn::Expr::Path(path) => path.qself.is_none() && path.path.get_ident().is_some(),
        syn::Expr::Field(field) => {
            matches!(field.member, syn::Member::Named(_)) && is_name_path(&field.base)
        }
        _ => false,
    }
}

/// The names a body declares: its elements, junctions, states, outputs, bond labels
/// and nested instances.
fn declared_names(body: &TokenStream) -> BTreeSet<String> {
    declared_idents(body).iter().map(Ident::to_string).collect()
}

/// [`declared_names`], as the identifiers written.
fn declared_idents(body: &TokenStream) -> Vec<Ident> {
    let mut names = Vec::new();
    for statement in statements(body.clone()) {
        let tokens = skip_attributes(&statement);
        let name = match tokens {
            [TokenTree::Ident(word), TokenTree::Ident(name), ..]
                if word == "state" || word == "output" =>
            {
                Some(name)
            }
            [TokenTree::Ident(word), ..] if word == "param" || word == "der" || word == "init" => {
                None
            }
            [TokenTree::Ident(_) | TokenTree::Literal(_), TokenTree::Ident(name), ..] => Some(name),
            [TokenTree::Ident(_) | TokenTree::Literal(_), TokenTree::Group(dim), TokenTree::Ident(name), ..]
                if dim.delimiter() == Delimiter::Bracket =>
            {
                Some(name)
            }
            _ => None,
        };
        names.extend(name.cloned());
        // Bond labels: `- [label] ->`.
        for pair in tokens.windows(2) {
            if let [TokenTree::Punct(dash), TokenTree::Group(group)] = pair {
                if dash.as_char() == '-' && group.delimiter() == Delimiter::Bracket {
                    if let Some(TokenTree::Ident(label)) = group.stream().into_iter().next() {
                        names.push(label);
                    }
                }
            }
        }
    }
    names
}

/// The submodel's body for one instance: locals prefixed, parameters substituted,
/// everything at the instance's span.
fn rewrite(
    body: TokenStream,
    instance: &Ident,
    locals: &BTreeSet<String>,
    substitutions: &BTreeMap<String, TokenStream>,
) -> TokenStream {
    let span = instance.span();
    let mut out = TokenStream::new();
    let mut after_dot = false;
    // The last two tokens were names: a parenthesised group now is a nested
    // instance's argument list, whose argument names belong to the other submodel.
    let mut names_before = 0;
    for tt in body {
        let next_after_dot = matches!(&tt, TokenTree::Punct(p) if p.as_char() == '.');
        let is_name = matches!(tt, TokenTree::Ident(_));
        match tt {
            TokenTree::Ident(ident) if !after_dot => {
                let word = ident.to_string();
                if locals.contains(&word) {
                    out.extend([TokenTree::Ident(prefixed(instance, &ident, span))]);
                } else if let Some(value) = substitutions.get(&word) {
                    out.extend(value.clone());
                } else {
                    out.extend([TokenTree::Ident(respanned(&ident, span))]);
                }
            }
            TokenTree::Group(group)
                if names_before >= 2 && group.delimiter() == Delimiter::Parenthesis =>
            {
                let mut args = TokenStream::new();
                for (i, arg) in split_arguments(group.stream()).into_iter().enumerate() {
                    if i > 0 {
                        args.extend([TokenTree::Punct(proc_macro2::Punct::new(
                            ',',
                            proc_macro2::Spacing::Alone,
                        ))]);
                    }
                    let mut arg = arg.into_iter();
                    // `name =` stays; the value is rewritten like any expression.
                    for tt in arg.by_ref().take(2) {
                        args.extend(respan(tt.into(), span));
                    }
                    args.extend(rewrite(arg.collect(), instance, locals, substitutions));
                }
                let mut new = Group::new(Delimiter::Parenthesis, args);
                new.set_span(span);
                out.extend([TokenTree::Group(new)]);
            }
            TokenTree::Group(group) => {
                let inner = rewrite(group.stream(), instance, locals, substitutions);
                let mut new = Group::new(group.delimiter(), inner);
                new.set_span(span);
                out.extend([TokenTree::Group(new)]);
            }
            mut other => {
                other.set_span(span);
                out.extend([other]);
            }
        }
        after_dot = next_after_dot;
        names_before = if is_name { names_before + 1 } else { 0 };
    }
    out
}

/// An argument list split at its top-level commas.
fn split_arguments(tokens: TokenStream) -> Vec<Vec<TokenTree>> {
    let mut args = vec![Vec::new()];
    for tt in tokens {
        match &tt {
            TokenTree::Punct(p) if p.as_char() == ',' => args.push(Vec::new()),
            _ => args.last_mut().map_or((), |arg| arg.push(tt)),
        }
    }
    args.retain(|arg| !arg.is_empty());
    args
}

fn respan(tokens: TokenStream, span: Span) -> TokenStream {
    tokens
        .into_iter()
        .map(|tt| match tt {
            TokenTree::Group(group) => {
                let mut new = Group::new(group.delimiter(), respan(group.stream(), span));
                new.set_span(span);
                TokenTree::Group(new)
            }
            mut other => {
                other.set_span(span);
                other
            }
        })
        .collect()
}

/// `inst . name` becomes `inst__name` wherever `inst` is an instance, repeatedly, so
/// `crank.A1.v` reaches a nested instance's junction.
fn merge_paths(tokens: TokenStream, instances: &BTreeSet<String>) -> TokenStream {
    let trees: Vec<TokenTree> = tokens.into_iter().collect();
    let mut out: Vec<TokenTree> = Vec::with_capacity(trees.len());
    let mut i = 0;
    while i < trees.len() {
        match &trees[i] {
            TokenTree::Group(group) => {
                let mut new = Group::new(group.delimiter(), merge_paths(group.stream(), instances));
                new.set_span(group.span());
                out.push(TokenTree::Group(new));
                i += 1;
            }
            TokenTree::Ident(ident) => {
                let preceded_by_dot =
                    matches!(out.last(), Some(TokenTree::Punct(p)) if p.as_char() == '.');
                let mut name = ident.clone();
                i += 1;
                while !preceded_by_dot && instances.contains(&name.to_string()) {
                    match (trees.get(i), trees.get(i + 1)) {
                        (Some(TokenTree::Punct(dot)), Some(TokenTree::Ident(member)))
                            if dot.as_char() == '.' =>
                        {
                            name = prefixed(&name, member, member.span());
                            i += 2;
                        }
                        _ => break,
                    }
                }
                out.push(TokenTree::Ident(name));
            }
            other => {
                out.push(other.clone());
                i += 1;
            }
        }
    }
    out.into_iter().collect()
}

#[cfg(test)]
mod should {
    use super::*;

    fn flat(submodels: &str, body: &str) -> (String, Vec<String>) {
        let (text, errors, _) = flat_placed(submodels, body);
        (text, errors)
    }

    fn flat_placed(submodels: &str, body: &str) -> (String, Vec<String>, Vec<Placed>) {
        let defs: Vec<SubmodelDef> = submodels
            .split("submodel")
            .filter(|s| !s.trim().is_empty())
            .map(|s| syn::parse_str(s).unwrap())
            .collect();
        let refs: Vec<&SubmodelDef> = defs.iter().collect();
        let mut errors = Vec::new();
        let mut placed = Vec::new();
        let tokens = flatten(body.parse().unwrap(), &refs, &mut errors, &mut placed);
        (
            tokens.to_string(),
            errors.iter().map(|e| e.to_string()).collect(),
            placed,
        )
    }

    #[test]
    fn record_every_instance_with_its_path_and_definition() {
        let (_, errors, placed) = flat_placed(
            "submodel Body(m) { 1 v; I p = m; v -> p; } submodel Arm(m) { Body upper(m = m); Body lower(m = m); }",
            "Body crank(m = 1.0); Arm arm(m = 2.0);",
        );
        assert!(errors.is_empty(), "{errors:?}");
        let placed: Vec<(&str, usize)> = placed
            .iter()
            .map(|p| (p.path.as_str(), p.submodel))
            .collect();
        assert_eq!(
            placed,
            [
                ("crank", 0),
                ("arm", 1),
                ("arm__upper", 0),
                ("arm__lower", 0)
            ]
        );
    }

    #[test]
    fn prefix_locals_substitute_parameters_and_merge_paths() {
        let (text, errors) = flat(
            "submodel Mass(m, g = 9.81) { I[3] p = m; 1 v; Se w = vec3(0.0, -m * g, 0.0); w -> v -> p; }",
            "Mass body(m = 2.0 * k); output y = body.v.f;",
        );
        assert!(errors.is_empty(), "{errors:?}");
        assert!(text.contains("I [3] body__p = (2.0 * k)"), "{text}");
        assert!(
            text.contains("Se body__w = vec3 (0.0 , - (2.0 * k) * (9.81) , 0.0)"),
            "{text}"
        );
        assert!(text.contains("body__w -> body__v -> body__p"), "{text}");
        assert!(text.contains("output y = body__v . f"), "{text}");
    }

    #[test]
    fn pass_an_instance_by_name_and_reach_nested_instances() {
        let (text, errors) = flat(
            "submodel Body(m) { 1 v; I p = m; v -> p; } submodel Point(body) { 0 at; body.v -> at; }",
            "Body crank(m = 1.0); Point tip(body = crank); output y = tip.at.e;",
        );
        assert!(errors.is_empty(), "{errors:?}");
        assert!(text.contains("crank__v -> tip__at"), "{text}");
        assert!(text.contains("output y = tip__at . e"), "{text}");
    }

    #[test]
    fn report_unknown_submodels_missing_and_unknown_arguments() {
        let (_, errors) = flat(
            "submodel Body(m, l) { I p = m; }",
            "Bdy a(m = 1.0); Body b(m = 1.0, q = 2.0);",
        );
        assert_eq!(errors.len(), 3, "{errors:?}");
        assert!(errors[0].starts_with("unknown submodel `Bdy`; the submodels are: Body"));
        assert!(errors[1].starts_with("submodel `Body` has no parameter `q`"));
        assert!(errors[2].starts_with("instance `b` of `Body` needs the parameter `l`"));
    }

    #[test]
    fn reserve_the_separator_for_instance_parts() {
        let (_, errors) = flat(
            "submodel Body(m) { I p = m; }",
            "C my__spring = 1.0; Body b(m = 1.0);",
        );
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert!(errors[0].starts_with("`my__spring`: names may not contain `__`"));
        assert!(errors[0].contains("help: rename it without `__`, e.g. `my_spring`"));
    }

    #[test]
    fn stop_a_submodel_that_instantiates_itself() {
        let (_, errors) = flat(
            "submodel Loop(m) { Loop inner(m = m); }",
            "Loop outer(m = 1.0);",
        );
        assert_eq!(errors.len(), 1);
        assert!(errors[0].contains("instantiates itself"));
        assert!(errors[0].contains("\nhelp: a submodel cannot contain an instance of itself"));
    }
}
