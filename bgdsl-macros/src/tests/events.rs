//! Events and modes through the whole pipeline: what reaches the generated code, and
//! the mistakes reported (compile-level behaviour is in `tests/tests/events_language.rs`
//! and `tests/ui/events/`).

fn expand(text: &str) -> String {
    crate::expand::expand(text.parse().unwrap()).to_string()
}

fn errors(text: &str) -> Vec<String> {
    let out = expand(text);
    out.split("compile_error !")
        .skip(1)
        .map(|rest| {
            let start = rest.find('"').unwrap() + 1;
            let end = rest[start..].find("\" }").map_or(rest.len(), |e| start + e);
            rest[start..end].to_string()
        })
        .collect()
}

const BALL: &str = r#"
    pub model Ball {
        param m = 1.0;
        param rest = 0.8;
        Se weight = -m * 9.81;
        I ball = m;
        1 v;
        weight -> v -> ball;
        state x: f64 = 1.0;
        der x = v.f;
        mode resting: bool = false;
        /// The ball hits the floor.
        when hit: x < 0.0 {
            if ball.p.abs() < 0.1 { resting = true; reinit ball.p = 0.0; }
            else { reinit ball.p = -rest * ball.p; }
        }
        when crossing(x - 2.0) { stop; }
        output held = if resting { 1.0 } else { 0.0 };
    }
"#;

#[test]
fn generate_modes_events_and_their_functions() {
    let out = expand(BALL);
    assert!(!out.contains("compile_error"), "{out}");
    assert!(out.contains("const MODES"), "{out}");
    assert!(out.contains("name : \"resting\""), "{out}");
    assert!(out.contains("name : \"hit\""), "{out}");
    assert!(out.contains("doc : \"The ball hits the floor.\""), "{out}");
    assert!(out.contains("name : \"when_2\""), "{out}");
    assert!(out.contains("Direction :: Falling"), "{out}");
    assert!(out.contains("Direction :: Both"), "{out}");
    assert!(out.contains("fn apply_event"), "{out}");
    assert!(out.contains("EventAction :: Stop"), "{out}");
    assert!(
        out.contains("STATE_NAMES : & 'static [& 'static :: core :: primitive :: str] = & [\"ball.p\" , \"x\" , \"resting\"]"),
        "{out}"
    );
}

#[test]
fn leave_a_model_without_events_as_it_was() {
    let out = expand("model M { C c = 1.0; I m = 1.0; 1 v; v -> { c, m }; }");
    assert!(!out.contains("MODES"));
    assert!(!out.contains("event_indicators"));
}

#[test]
fn prefix_modes_and_events_of_a_submodel() {
    let out = expand(
        r#"
        submodel Stop(body, at) {
            mode hit_once: bool = false;
            when body.p > at { reinit body.p = 0.0; hit_once = true; }
        }
        model M { Se push = 1.0; I mass = 1.0; push -> mass; Stop end(body = mass, at = 2.0); }
        "#,
    );
    assert!(!out.contains("compile_error"), "{out}");
    assert!(out.contains("\"end.hit_once\""), "{out}");
    assert!(out.contains("name : \"end.when_1\""), "{out}");
}

#[test]
fn report_reinit_of_what_is_no_state() {
    let messages = errors(
        r#"model M { param k = 1.0; C c = k; I m = 1.0; 1 v; v -> { c, m }; mode on: bool = false;
           when c.q > 1.0 { reinit k = 0.0; reinit c.e = 0.0; reinit on = true; reinit m.q = 1.0; on = true; } }"#,
    );
    assert_eq!(messages.len(), 4, "{messages:?}");
    assert!(
        messages[0].starts_with("`k` is a parameter, not a state"),
        "{messages:?}"
    );
    assert!(
        messages[1].starts_with("`c.e` is not a state"),
        "{messages:?}"
    );
    assert!(
        messages[2].starts_with("`on` is a mode, not a state"),
        "{messages:?}"
    );
    assert!(
        messages[3].starts_with("`m.q` is not a state"),
        "{messages:?}"
    );
}

#[test]
fn report_conditions_that_are_no_comparison() {
    let messages = errors(
        r#"model M { C c = 1.0; I m = 1.0; 1 v; v -> { c, m }; mode on: bool = false;
           when c.q { on = true; } when c.q == 1.0 { on = true; } when c.q > 1.0 && m.p > 0.0 { on = false; } }"#,
    );
    assert_eq!(messages.len(), 3, "{messages:?}");
    assert!(messages[0].starts_with("a `when` condition is a comparison or a crossing"));
    assert!(messages[1].contains("`==` and `!=` are no conditions"));
    assert!(messages[2].contains("`&&` and `||` combine none"));
}

#[test]
fn report_unknown_modes_and_empty_whens() {
    let messages = errors(
        r#"model M { C c = 1.0; I m = 1.0; 1 v; v -> { c, m }; mode stuck: bool = false;
           output g = if stuck { 1.0 } else { 0.0 }; when c.q > 1.0 { stuk = true; } when c.q < 0.0 { } }"#,
    );
    assert_eq!(messages.len(), 2, "{messages:?}");
    assert!(
        messages[0].starts_with("unknown mode `stuk`"),
        "{messages:?}"
    );
    assert!(
        messages[0].contains("did you mean `stuck`?"),
        "{messages:?}"
    );
    assert!(
        messages[1].starts_with("event `when_2` has no action"),
        "{messages:?}"
    );
}

#[test]
fn report_a_mode_read_but_never_switched() {
    let messages = errors(
        r#"model M { C c = 1.0; I m = 1.0; 1 v; v -> { c, m }; mode gear: i64 = 1; mode on: bool = false;
           output g = if gear == 2 { 1.0 } else { 0.0 }; when c.q > 1.0 { on = true; } }"#,
    );
    assert_eq!(messages.len(), 1, "{messages:?}");
    assert!(
        messages[0].starts_with("mode `gear` is read but never switched"),
        "{messages:?}"
    );
}

#[test]
fn never_panic_on_malformed_whens() {
    for body in [
        "when",
        "when {}",
        "when c.q > 0.0",
        "when c.q > 0.0 { reinit }",
        "when c.q > 0.0 { reinit c.q }",
        "when c.q > 0.0 { reinit c.q = ; }",
        "when c.q > 0.0 { if { } }",
        "when c.q > 0.0 { if c.q > 1.0 { stop; } else }",
        "when c.q > 0.0 { stop }",
        "when crossing() { stop; }",
        "when crossing(1.0, 2.0) { stop; }",
        "when a: { stop; }",
        "when a: b: c.q > 0.0 { stop; }",
        "when c.q > 0.0 { x = ; }",
        "when c.q > 0.0 { 3 = 4; }",
        "mode",
        "mode x",
        "mode x: u8 = 1;",
        "mode x: bool;",
        "when c.q[0] > 0.0 { stop; }",
    ] {
        let text = format!("model M {{ C c = 1.0; I m = 1.0; 1 v; v -> {{ c, m }}; {body} }}");
        let out = expand(&text);
        assert!(out.contains("compile_error"), "{body}: {out}");
    }
}

#[test]
fn report_each_malformed_when_and_read_on() {
    let messages = errors(
        r#"model M { Se push = 1.0; I mass = 1.0; push -> mass; mode on: bool = false;
           when { on = true; }
           when mass.p > 1.0 { on == true; }
           when mass.p > 2.0 { reinit mass.p; }
           C spring = 1.0 }"#,
    );
    assert_eq!(messages.len(), 4, "{messages:?}");
    assert!(messages[0].starts_with("expected a condition before the actions"));
    assert!(messages[1].starts_with("expected an action"));
    assert!(messages[2].starts_with("expected `=`"), "{messages:?}");
    assert!(messages[3].starts_with("expected `;`"), "{messages:?}");
}

/// Random `when` blocks and `mode` declarations made of the language's pieces (a
/// seeded generator, so every run tests the same 2000 cases): each expands to code or
/// to compile errors, never to a panic of the macro.
#[test]
fn never_panic_on_random_event_statements() {
    const PIECES: &[&str] = &[
        "when", "mode", "reinit", "stop", "crossing", "if", "else", "c.q", "m.p", "on", "n", "x",
        "t", "1.0", "0", "true", "<", ">", "<=", "==", "&&", "=", ";", ":", ",", ".", "-", "+",
        "(", ")", "{", "}", "{ }", "bool", "i64", "f64", "hit", "v.f", "[0]",
    ];
    let mut seed: u64 = 0x5EED_0FE7_E7E7;
    let mut next = |n: usize| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 33) as usize) % n
    };
    let (mut expanded, mut rejected) = (0, 0);
    for _ in 0..2000 {
        let length = 1 + next(14);
        let mut text = String::new();
        let mut depth = (0i32, 0i32);
        for _ in 0..length {
            let piece = PIECES[next(PIECES.len())];
            match piece {
                "(" => depth.0 += 1,
                ")" if depth.0 == 0 => continue,
                ")" => depth.0 -= 1,
                "{" => depth.1 += 1,
                "}" if depth.1 == 0 => continue,
                "}" => depth.1 -= 1,
                _ => {}
            }
            text.push_str(piece);
            text.push(' ');
        }
        text.push_str(&")".repeat(depth.0 as usize));
        text.push_str(&"}".repeat(depth.1 as usize));
        let model = format!(
            "model M {{ C c = 1.0; I m = 1.0; 1 v; v -> {{ c, m }}; mode on: bool = false; \
             mode n: i64 = 0; state x: f64 = 0.0; der x = v.f; when c.q > 0.5 {{ on = true; n = n + 1; }} \
             {text} }}"
        );
        let Ok(tokens) = model.parse() else {
            continue;
        };
        let out = crate::expand::expand(tokens).to_string();
        expanded += 1;
        rejected += usize::from(out.contains("compile_error"));
    }
    // Most token soups are mistakes; the cases reach the stages past parsing too.
    assert!(
        expanded > 1500 && rejected > 1000 && expanded > rejected,
        "{expanded} {rejected}"
    );
}
