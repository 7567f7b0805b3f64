# Shared by the benchmark scripts (sourced, not run): installing the peers and tools, timing a
# command, and pairing two. Benchmarks only: nothing here is used by the product or its tests.

as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }

# need_package COMMAND PACKAGE: installs Debian's PACKAGE unless COMMAND is already there.
need_package() {
    if ! command -v "$1" >/dev/null 2>&1; then
        as_root apt-get install -y "$2" >/dev/null || { as_root apt-get update >/dev/null && as_root apt-get install -y "$2" >/dev/null; }
    fi
}

# What every benchmark script needs: GDAL (the peer), jq (reports) and GNU time (peak RSS).
need_bench_tools() {
    need_package gdal_translate gdal-bin
    need_package jq jq
    [ -x /usr/bin/time ] || need_package /usr/bin/time time
}

# timed_runs RUNS COMMAND...: runs COMMAND RUNS times (its output in run.log, printed if it
# fails) and sets WALL_S, the median wall time in seconds (timed in nanoseconds around the
# command), and PEAK_RSS_MB, the largest peak resident set of the runs (GNU time). BEFORE_RUN,
# if set, is evaluated before each run (to remove the previous outputs).
timed_runs() {
    local runs=$1
    shift
    local walls=() rss=0 k start end
    for ((k = 0; k < runs; ++k)); do
        [ -n "${BEFORE_RUN:-}" ] && eval "$BEFORE_RUN"
        start=$(date +%s%N)
        /usr/bin/time -v -o time.txt "$@" >run.log 2>&1 || { cat run.log; exit 1; }
        end=$(date +%s%N)
        walls+=("$(awk -v ns=$((end - start)) 'BEGIN {printf "%.3f", ns / 1e9}')")
        rss=$(awk -F': ' -v r="$rss" '/Maximum resident set size/ {m = $2 / 1024; printf "%.0f", (m > r ? m : r)}' time.txt)
    done
    WALL_S=$(printf '%s\n' "${walls[@]}" | sort -n | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}')
    PEAK_RSS_MB=$rss
}

# build_programs TARGET...: configures $BUILD as a Release build without GL if it is not configured
# yet, and builds the TARGETs in it. program_path NAME: the path of the built program NAME.
build_programs() {
    if [ ! -f "$BUILD/CMakeCache.txt" ]; then
        cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DPYRAMID_WITH_GL=OFF >/dev/null
    fi
    cmake --build "$BUILD" -j"$(nproc)" --target "$@" >/dev/null
}
program_path() { find "$BUILD" -name "$1" -type f -perm -u+x | head -n 1; }

# median VALUE...: the middle value (the upper middle one of an even count).
median() { printf '%s\n' "$@" | sort -n | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }

# paired_runs PAIRS: runs the command in the array PAIR_A, then the one in PAIR_B, PAIRS times in
# turn (A B A B ...; PAIR_A_CLEAN and PAIR_B_CLEAN, if set, are evaluated before each of their
# runs), and sets A_S and B_S (the median wall times), RATIO (the median of the pairs' A / B) and
# A_RSS_MB and B_RSS_MB (the largest peak RSS of each).
paired_runs() {
    local a=() b=() ratios=() k
    A_RSS_MB=0 B_RSS_MB=0
    for ((k = 0; k < $1; ++k)); do
        BEFORE_RUN=${PAIR_A_CLEAN:-} timed_runs 1 "${PAIR_A[@]}"
        a+=("$WALL_S")
        A_RSS_MB=$((PEAK_RSS_MB > A_RSS_MB ? PEAK_RSS_MB : A_RSS_MB))
        BEFORE_RUN=${PAIR_B_CLEAN:-} timed_runs 1 "${PAIR_B[@]}"
        b+=("$WALL_S")
        B_RSS_MB=$((PEAK_RSS_MB > B_RSS_MB ? PEAK_RSS_MB : B_RSS_MB))
        ratios+=("$(awk -v x="${a[k]}" -v y="$WALL_S" 'BEGIN {printf "%.3f", x / y}')")
    done
    A_S=$(median "${a[@]}") B_S=$(median "${b[@]}") RATIO=$(median "${ratios[@]}")
}

# markdown_table TSV HEADER FORMAT: the rows of TSV (its first line, the column names, skipped) as
# a Markdown table under HEADER (the column titles separated by |), each row printed with awk's
# printf FORMAT over its first seven fields; then where the raw figures are.
markdown_table() {
    echo
    awk -F'\t' -v header="$2" -v format="$3" '
        NR == 1 { n = split(header, h, "|"); line = "|"; rule = "|"
                  for (i = 1; i <= n; ++i) { line = line " " h[i] " |"; rule = rule "---|" }
                  print line; print rule; next }
        { printf format, $1, $2, $3, $4, $5, $6, $7 }' "$1"
    echo "raw figures: $1"
}
