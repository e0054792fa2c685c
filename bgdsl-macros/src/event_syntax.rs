//! Stage 1, events: the syntax of `mode` declarations and `when` blocks.
//!
//! ```text
//! doc* "mode" name ":" ("bool" | "i64" | "f64") "=" expr
//! doc* "when" (label ":")? condition "{" action* "}"
//! action := "reinit" name ("." name)? "=" expr ";" | name "=" expr ";" | "stop" ";"
//!         | "if" expr "{" action* "}" ("else" ("{" action* "}" | if-action))?
//! ```
//!
//! The condition is kept as the expression written; [`crate::events`] reads it as a
//! comparison or `crossing(..)` and reports anything else at its text.

use proc_macro2::Span;
use syn::ext::IdentExt;
use syn::parse::ParseStream;
use syn::{braced, Attribute, Expr, Ident, Token};

/// Words of the event syntax.
pub mod kw {
    syn::custom_keyword!(mode);
    syn::custom_keyword!(when);
    syn::custom_keyword!(reinit);
    syn::custom_keyword!(stop);
}

/// The value type of a mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeKind {
    /// `bool`: stored as 0.0 or 1.0.
    Bool,
    /// `i64`: stored as an integral value.
    Integer,
    /// `f64`: stored as itself.
    Real,
}

/// `mode stuck: bool = false;`
pub struct ModeDecl {
    /// Doc comments: the mode's documentation.
    pub attrs: Vec<Attribute>,
    /// The mode's name.
    pub name: Ident,
    /// Its value type.
    pub kind: ModeKind,
    /// Its initial value, an expression in parameters.
    pub init: Expr,
}

/// `when hit: ball.q < 0.0 { reinit ball.p = -e * ball.p; }`
pub struct WhenDecl {
    /// Doc comments: the event's documentation.
    pub attrs: Vec<Attribute>,
    /// The `when` keyword.
    pub span: Span,
    /// The event's name (given, or `when_k` from [`crate::flatten`]).
    pub label: Option<Ident>,
    /// The condition as written.
    pub condition: Expr,
    /// Where the braces of the actions are.
    pub body: Span,
    /// The actions, in order.
    pub actions: Vec<ActionSyntax>,
}

/// One action of a `when` block.
pub enum ActionSyntax {
    /// `reinit ball.p = value;` or `reinit theta = value;`
    Reinit {
        /// The element or kinematic state.
        target: Ident,
        /// `.p` / `.q`, for an element.
        member: Option<Ident>,
        /// The new value.
        value: Expr,
    },
    /// `stuck = true;`
    Assign {
        /// The mode.
        target: Ident,
        /// The new value.
        value: Expr,
    },
    /// `stop;`
    Stop,
    /// `if cond { .. } else { .. }`
    If {
        /// The condition (pre-event values).
        cond: Expr,
        /// Actions when it holds.
        then: Vec<ActionSyntax>,
        /// Actions otherwise.
        otherwise: Vec<ActionSyntax>,
    },
}

/// `mode name: type = expr` (after the `mode` keyword's lookahead).
pub fn parse_mode(input: ParseStream, attrs: Vec<Attribute>) -> syn::Result<ModeDecl> {
    input.parse::<kw::mode>()?;
    let name = input.call(Ident::parse_any)?;
    input.parse::<Token![:]>()?;
    let ty = input.call(Ident::parse_any)?;
    let kind = match ty.to_string().as_str() {
        "bool" => ModeKind::Bool,
        "i64" => ModeKind::Integer,
        "f64" => ModeKind::Real,
        _ => {
            return Err(syn::Error::new(
                ty.span(),
                format!(
                    "a mode is a `bool`, an `i64` or an `f64`, not `{ty}`: `mode {name}: bool = false;`"
                ),
            ))
        }
    };
    input.parse::<Token![=]>()?;
    let init = input.parse()?;
    Ok(ModeDecl {
        attrs,
        name,
        kind,
        init,
    })
}

/// `when (label :)? condition { actions }`
pub fn parse_when(input: ParseStream, attrs: Vec<Attribute>) -> syn::Result<WhenDecl> {
    let keyword = input.parse::<kw::when>()?;
    let label = if input.peek(Ident::peek_any) && input.peek2(Token![:]) && !input.peek2(Token![::])
    {
        let label = input.call(Ident::parse_any)?;
        input.parse::<Token![:]>()?;
        Some(label)
    } else {
        None
    };
    if input.peek(syn::token::Brace) {
        return Err(input.error(
            "expected a condition before the actions: `when ball.q < 0.0 { .. }`, \
             `when v > 0.0 { .. }` or `when crossing(v) { .. }`",
        ));
    }
    let condition = Expr::parse_without_eager_brace(input)?;
    if !input.peek(syn::token::Brace) {
        return Err(input.error(
            "expected `{` after the condition: a `when` takes its actions in braces, \
             `when ball.q < 0.0 { reinit ball.p = -ball.p; }`",
        ));
    }
    let body;
    let brace = braced!(body in input);
    let actions = crate::syntax::parse_group(&body, parse_actions)?;
    Ok(WhenDecl {
        attrs,
        span: keyword.span,
        label,
        condition,
        body: brace.span.join(),
        actions,
    })
}

fn parse_actions(input: ParseStream) -> syn::Result<Vec<ActionSyntax>> {
    let mut actions = Vec::new();
    while !input.is_empty() {
        actions.push(parse_action(input)?);
    }
    Ok(actions)
}

fn parse_action(input: ParseStream) -> syn::Result<ActionSyntax> {
    if input.peek(kw::reinit) && !input.peek2(Token![=]) {
        input.parse::<kw::reinit>()?;
        let target = input.call(Ident::parse_any)?;
        let member = if input.peek(Token![.]) {
            input.parse::<Token![.]>()?;
            Some(input.call(Ident::parse_any)?)
        } else {
            None
        };
        input.parse::<Token![=]>()?;
        let value = input.parse()?;
        input.parse::<Token![;]>()?;
        return Ok(ActionSyntax::Reinit {
            target,
            member,
            value,
        });
    }
    if input.peek(kw::stop) && input.peek2(Token![;]) {
        input.parse::<kw::stop>()?;
        input.parse::<Token![;]>()?;
        return Ok(ActionSyntax::Stop);
    }
    if input.peek(Token![if]) {
        return parse_if(input);
    }
    if input.peek(Ident::peek_any) && input.peek2(Token![=]) && !input.peek2(Token![==]) {
        let target = input.call(Ident::parse_any)?;
        input.parse::<Token![=]>()?;
        let value = input.parse()?;
        input.parse::<Token![;]>()?;
        return Ok(ActionSyntax::Assign { target, value });
    }
    Err(input.error(
        "expected an action: `reinit ball.p = value;` (a state), `mode = value;` (a mode), \
         `stop;` or `if condition { .. } else { .. }`",
    ))
}

fn parse_if(input: ParseStream) -> syn::Result<ActionSyntax> {
    input.parse::<Token![if]>()?;
    let cond = Expr::parse_without_eager_brace(input)?;
    let body;
    braced!(body in input);
    let then = crate::syntax::parse_group(&body, parse_actions)?;
    let otherwise = if input.peek(Token![else]) {
        input.parse::<Token![else]>()?;
        if input.peek(Token![if]) {
            vec![parse_if(input)?]
        } else {
            let body;
            braced!(body in input);
            crate::syntax::parse_group(&body, parse_actions)?
        }
    } else {
        Vec::new()
    };
    Ok(ActionSyntax::If {
        cond,
        then,
        otherwise,
    })
}
