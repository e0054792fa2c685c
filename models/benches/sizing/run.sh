#!/usr/bin/env bash
# The sizing benchmark: what a `bond_graph!` model costs as it grows. For chains of N
# states (generate.sh: `scalar`, the mass-spring-damper chain, 2 states a cell; `rigid`,
# the standard library's RigidBody joined by Couplings, 21 states a body) it builds a
# throwaway crate in /tmp and prints a markdown table of: macro expansion time and bytes
# of generated Rust per state, release build time and rustc's peak memory (max RSS from
# /usr/bin/time -v), binary size and the largest generated functions (symbol table),
# one right-hand side, one Jacobian and a short solve (program.rs, with a hand-written
# chain's right-hand side as the anchor), then the growth exponents (least squares on
# log-log, over the sizes >= 1,000 states when there are two, else all).
#
#   models/benches/sizing/run.sh                  # N = 100, 1,000, 2,000, 5,000, 10,000; both chains
#   models/benches/sizing/run.sh --quick          # stops at 1,000 states
#   models/benches/sizing/run.sh --dev            # also times the dev-profile build
#   SIZES="200 400" KINDS=scalar models/benches/sizing/run.sh
#   SIZING_T_END=0.01 SIZING_STIFF_MAX=2000 SIZING_JACOBIAN_MAX=20000  # program.rs's knobs
#
# Long (the 10,000-state builds take minutes each): not run in CI; use `nice -n 10`. On a
# shared machine compare the build's CPU seconds (user + system), not its wall time.
# Dependencies are built once into $SIZING_TARGET_DIR (default /tmp/bgdsl-sizing-target,
# kept between runs; delete it when done); each model's crate is rebuilt from scratch
# (CARGO_INCREMENTAL=0) after a touch, so the build time is the model's own.
set -euo pipefail
shopt -s inherit_errexit

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
export CARGO_TARGET_DIR="${SIZING_TARGET_DIR:-/tmp/bgdsl-sizing-target}"
export CARGO_INCREMENTAL=0
# v0 symbol names tell the instances of a generic function apart (derivatives::<f64>).
export RUSTFLAGS="-C symbol-mangling-version=v0"
sizes="${SIZES:-100 1000 2000 5000 10000}"
kinds="${KINDS:-scalar rigid}"
dev=no
for arg in "$@"; do
    case "$arg" in
    --quick) sizes="${SIZES:-100 1000}" ;;
    --dev) dev=yes ;;
    *) echo "run.sh: unknown argument $arg (--quick, --dev)" >&2; exit 2 ;;
    esac
done
work="$(mktemp -d /tmp/bgdsl-sizing.XXXXXX)"
trap 'rm -rf "$work"' EXIT

manifest() { # NAME DEPENDENCIES
    cat <<TOML
[package]
name = "$1"
version = "0.1.0"
edition = "2021"
publish = false

[dependencies]
$2

[profile.release]
debug = false

[workspace]
TOML
}

# The macro timer: the macro crate's modules compiled into a plain program.
expander="$work/expander"
mkdir -p "$expander/src"
cp "$root/rust-toolchain.toml" "$root/Cargo.lock" "$expander/"
manifest sizing-expand "proc-macro2 = \"1\"
quote = \"1\"
syn = { version = \"2\", features = [\"full\", \"visit\", \"visit-mut\", \"extra-traits\"] }
bgdsl-units = { path = \"$root/bgdsl-units\" }" >"$expander/Cargo.toml"
{
    cat "$here/expand.rs"
    for f in "$root"/bgdsl-macros/src/*.rs; do
        m="$(basename "$f" .rs)"
        [ "$m" = lib ] && continue
        echo "#[path = \"$f\"] mod $m;"
    done
    for d in "$root"/bgdsl-macros/src/*/mod.rs; do
        m="$(basename "$(dirname "$d")")"
        [ "$m" = tests ] && continue
        echo "#[path = \"$d\"] mod $m;"
    done
} >"$expander/src/main.rs"
(cd "$expander" && cargo build --quiet --release)
expand_bin="$CARGO_TARGET_DIR/release/sizing-expand"

# kv FILE KEY: the value of KEY=... in FILE, or "-".
kv() { grep -m1 "^$2=" "$1" | cut -d= -f2- || echo -; }

results="$work/results.tsv"
: >"$results"
for kind in $kinds; do
    for n in $sizes; do
        crate="$work/sizing-$kind-$n"
        mkdir -p "$crate/src"
        cp "$root/rust-toolchain.toml" "$root/Cargo.lock" "$crate/"
        manifest sizing-model "bgdsl-runtime = { path = \"$root/bgdsl-runtime\" }" >"$crate/Cargo.toml"
        name=$([ "$kind" = scalar ] && echo Chain || echo Bodies)
        { "$here/generate.sh" "$kind" "$n"; echo "pub type Subject = $name;"; } >"$crate/src/model.rs"
        cp "$here/program.rs" "$crate/src/main.rs"
        log="$crate/log"
        "$expand_bin" "$crate/src/model.rs" >"$log"
        # Dependencies first (not timed): a crate without the model.
        mv "$crate/src/model.rs" "$crate/model.rs"
        echo "pub struct Subject;" >"$crate/src/model.rs"
        (cd "$crate" && echo 'fn main() {}' >src/main.rs && cargo build --quiet --release 2>/dev/null)
        mv "$crate/model.rs" "$crate/src/model.rs"
        cp "$here/program.rs" "$crate/src/main.rs"
        for profile in release $([ "$dev" = yes ] && echo dev); do
            flag=$([ "$profile" = release ] && echo --release || echo)
            touch "$crate/src/main.rs"
            start=$(date +%s.%N)
            (cd "$crate" && \
                /usr/bin/time -v -o "$crate/time-$profile" cargo build --quiet $flag)
            end=$(date +%s.%N)
            echo "build_${profile}_s=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')" >>"$log"
            echo "rss_${profile}_mb=$(awk '/Maximum resident/ { printf "%.0f", $NF / 1024 }' "$crate/time-$profile")" >>"$log"
            # CPU seconds (user + system): what the build costs on a shared machine.
            echo "cpu_${profile}_s=$(awk '/User time|System time/ { t += $NF } END { printf "%.1f", t }' "$crate/time-$profile")" >>"$log"
        done
        bin="$CARGO_TARGET_DIR/release/sizing-model"
        echo "binary_kb=$(( $(stat -c %s "$bin") / 1024 ))" >>"$log"
        # Generated functions: the model's methods, by instance.
        nm -C --size-sort --radix=d "$bin" | grep -F "$name as bgdsl_runtime::model::Model>::" |
            sed -E 's/^0*([0-9]+) . .*Model>::([a-z_]+)(::<(.*)>)?$/\1 \2<\4>/; s/bgdsl_runtime::dual::DualN/DualN/; s/<>$//' >"$crate/functions"
        awk '{ size[$2] += $1; copies[$2] += 1 } END { for (f in size) printf "fn_%s=%d/%d\n", f, size[f], copies[f] }' \
            "$crate/functions" >>"$log"
        SIZING_T_END="${SIZING_T_END:-0.01}" nice -n 0 "$bin" >>"$log"
        states=$(kv "$log" states)
        printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' \
            "$kind" "$states" "$(kv "$log" expand_s)" "$(kv "$log" rust_bytes)" \
            "$(kv "$log" build_release_s)" "$(kv "$log" rss_release_mb)" \
            "$(kv "$log" build_dev_s)" "$(kv "$log" rss_dev_mb)" "$(kv "$log" binary_kb)" \
            "$(kv "$log" 'fn_derivatives<f64>')" "$(kv "$log" 'fn_derivatives<DualN<4>>')" \
            "$(kv "$log" 'fn_outputs<f64>')" "$(kv "$log" 'fn_power_balance<f64>')" \
            "$(kv "$log" rhs_us)" "$(kv "$log" anchor_us)" "$(kv "$log" jacobian_us)" \
            "$(kv "$log" dopri5_ms)" "$(kv "$log" radau5_ms)" "$(kv "$log" power_us)" "$(kv "$log" cpu_release_s)" >>"$results"
        echo "done: $kind $states states ($(kv "$log" build_release_s) s, $(kv "$log" rss_release_mb) MB)" >&2
        [ -n "${SIZING_KEEP:-}" ] && cp -r "$crate" "$SIZING_KEEP/" 
        rm -rf "$crate"
    done
done

echo
echo "| chain | states | macro s | Rust B/state | release build s | rustc MB | dev build s | dev MB | binary KB | derivatives<f64> B/copies | derivatives<DualN<4>> B/copies | outputs<f64> B/copies | power_balance<f64> B/copies | RHS µs | anchor µs | Jacobian µs | dopri5 ms | radau5 ms | power µs | release CPU s |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
awk -F'\t' 'BEGIN { OFS = " | " } {
    per = ($4 == "-") ? "-" : sprintf("%.0f", $4 / $2)
    print "| " $1, $2, $3, per, $5, $6, $7, $8, $9, $10, $11, $12, $13, $14, $15, $16, $17, $18, $19, $20 " |"
}' "$results"
echo
echo "Growth exponents (least squares of log(value) on log(states); sizes >= 1,000 when two or more):"
for kind in $kinds; do
    awk -F'\t' -v kind="$kind" '
    $1 == kind { n++; s[n] = $2; for (c = 3; c <= 20; c++) v[n, c] = $c }
    END {
        split("macro,Rust bytes,release build,rustc MB,dev build,dev MB,binary,,,,,RHS,anchor,Jacobian,dopri5,radau5,power,release CPU", name, ",")
        big = 0; for (i = 1; i <= n; i++) if (s[i] >= 1000) big++
        line = "  " kind ":"
        for (c = 3; c <= 20; c++) {
            if (name[c - 2] == "") continue
            m = 0; sx = sy = sxx = sxy = 0
            for (i = 1; i <= n; i++) {
                if (big >= 2 && s[i] < 1000) continue
                split(v[i, c], parts, "/"); y = parts[1]
                if (y == "-" || y + 0 <= 0) continue
                x = log(s[i]); y = log(y + 0); m++; sx += x; sy += y; sxx += x * x; sxy += x * y
            }
            if (m >= 2 && m * sxx - sx * sx > 0) line = line sprintf(" %s N^%.2f;", name[c - 2], (m * sxy - sx * sy) / (m * sxx - sx * sx))
        }
        print line
    }' "$results"
done
