#!/usr/bin/env bash
# What `bond_graph!` costs at build time: builds two throwaway crates that differ only
# in a 50-element model (8 mass-spring-damper cells in a chain, 49 bonds), each $RUNS times
# after `touch`, and prints the median wall time of each and the difference.
#
#   models/benches/macro_cost.sh            # dev profile (what an edit-compile loop pays)
#   models/benches/macro_cost.sh --release  # any extra arguments go to `cargo build`
#   RUNS=5 models/benches/macro_cost.sh    # more timed runs (default 3)
#
# Dependencies (bgdsl-runtime, the macro crate, syn, serde) are built once, before the
# timed runs, into a fixed target directory shared by both crates and kept between
# invocations: $MACRO_COST_TARGET_DIR, by default $TMPDIR/bgdsl-macro-cost-target.
# The timed builds therefore recompile only the throwaway crate itself, from scratch:
# CARGO_INCREMENTAL defaults to 0 here, because an incremental rebuild of an untouched
# file reuses the generated code and would hide most of what the model costs (set
# CARGO_INCREMENTAL=1 to measure that case).
set -euo pipefail
shopt -s inherit_errexit

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
export CARGO_TARGET_DIR="${MACRO_COST_TARGET_DIR:-${TMPDIR:-/tmp}/bgdsl-macro-cost-target}"
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
runs="${RUNS:-3}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# The model: a force on a chain of cells; cell i is a mass (1 v_i, I m_i) tied to the
# next by a spring and damper in parallel (0 n_i, 1 d_i, C k_i, R r_i); plus the source
# and a damper to ground: 8 * 6 + 2 = 50 elements.
model() {
    local cells=8
    echo "bgdsl_runtime::bond_graph! {"
    echo "    pub model Chain {"
    echo "        param m = 1.0; param k = 100.0; param c = 0.5; param force = 1.0;"
    echo "        Se source = force * (3.0 * t).sin();"
    echo "        R ground = c;"
    echo "        source -> v1; v1 -> ground;"
    for i in $(seq 1 "$cells"); do
        echo "        1 v$i; I m$i = m * $i.0; 0 n$i; 1 d$i; C k$i = k / $i.0; R r$i = c + 0.1 * $i.0;"
        echo "        v$i -> { m$i, n$i }; n$i -> d$i -> { k$i, r$i };"
        if [ "$i" -lt "$cells" ]; then echo "        n$i -> v$((i + 1));"; fi
    done
    echo "        output x1 = k1.q;"
    echo "    }"
    echo "}"
}

# make_crate NAME WITH_MODEL
make_crate() {
    local dir="$work/$1"
    mkdir -p "$dir/src"
    cp "$root/rust-toolchain.toml" "$root/Cargo.lock" "$dir/"
    cat >"$dir/Cargo.toml" <<TOML
[package]
name = "$1"
version = "0.1.0"
edition = "2021"
publish = false

[dependencies]
bgdsl-runtime = { path = "$root/bgdsl-runtime" }

[workspace]
TOML
    {
        echo "use bgdsl_runtime::Model;"
        if [ "$2" = yes ]; then
            model
            echo "fn main() {"
            echo "    let chain = Chain::default();"
            echo "    let mut x = [0.0; Chain::N_STATES];"
            echo "    let mut dx = [0.0; Chain::N_STATES];"
            echo "    chain.initial_state(&mut x);"
            echo "    chain.derivatives(0.1, &x, &mut dx);"
            echo "    println!(\"{} states, {:?}\", <Chain as Model>::STATE_NAMES.len(), dx);"
            echo "}"
        else
            echo "fn main() {"
            echo "    let names: &[&str] = <() as Named>::NAMES;"
            echo "    println!(\"{} states\", names.len());"
            echo "}"
            echo "trait Named { const NAMES: &'static [&'static str]; }"
            echo "impl Named for () { const NAMES: &'static [&'static str] = &[]; }"
            echo "#[allow(dead_code)] fn uses_the_runtime<M: Model>() -> usize { M::N_STATES }"
        fi
    } >"$dir/src/main.rs"
}

now() { date +%s.%N; }

# median_build NAME: prints the median of $runs timed builds after touching main.rs.
median_build() {
    local dir="$work/$1" times=()
    (cd "$dir" && cargo build --quiet "${@:2}")   # dependencies, not timed
    for _ in $(seq "$runs"); do
        touch "$dir/src/main.rs"
        local start end
        start="$(now)"
        (cd "$dir" && cargo build --quiet "${@:2}")
        end="$(now)"
        times+=("$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')")
    done
    printf '%s\n' "${times[@]}" | sort -g | sed -n "$(((runs + 1) / 2))p"
}

make_crate macro_cost_without no
make_crate macro_cost_with yes
without="$(median_build macro_cost_without "$@")"
with="$(median_build macro_cost_with "$@")"
printf 'cargo build %s (CARGO_INCREMENTAL=%s), median of %d runs after touch:\n' \
    "${*:-(dev)}" "$CARGO_INCREMENTAL" "$runs"
printf '  without the model:          %6.3f s\n' "$without"
printf '  with a 50-element model:    %6.3f s\n' "$with"
printf '  cost of the model:          %6.3f s\n' "$(awk -v a="$without" -v b="$with" 'BEGIN { print b - a }')"
