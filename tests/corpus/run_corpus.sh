#!/usr/bin/env bash
# Runs `photonbridge info` over the loader corpus and checks every outcome.
#
#   bash tests/corpus/run_corpus.sh PB_EXE ROOT [CORPUS_DIR]
#
# PB_EXE is the photonbridge binary, ROOT the source root; CORPUS_DIR defaults
# to ROOT/tests/corpus. Each line of CORPUS_DIR/expected.tsv (see
# make_corpus.py) is one run, with a 10 s time limit, checked for:
#   - the exact exit status;
#   - failures: stderr is exactly one line that names the file and contains
#     every '|'-separated EXPECT substring;
#   - successes: empty stderr, and on `info --json -` every 'triangles=N' and
#     'warn=SUBSTRING' check;
#   - no sanitizer report and no time-out, whatever the case.
# Prints one line per case, then "N passed, N failed"; exits 1 on any failure.
set -u

if [ $# -lt 2 ]; then
  echo "usage: $0 PB_EXE ROOT [CORPUS_DIR]" >&2
  exit 2
fi
exe=$1
root=$2
corpus=${3:-$root/tests/corpus}
manifest=$corpus/expected.tsv
[ -x "$exe" ] || { echo "run_corpus: $exe is not an executable" >&2; exit 2; }
[ -f "$manifest" ] || { echo "run_corpus: $manifest not found" >&2; exit 2; }

# Sanitizers: report and fail hard; keep the report on stderr where we look.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:exitcode=99}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1:exitcode=98}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
failed_names=()

# Runs from the corpus folder so that messages carry the short relative path.
cd "$corpus" || exit 2

while IFS=$'\t' read -r path code expect args || [ -n "$path" ]; do
  case $path in '' | '#'*) continue ;; esac
  extra=()
  [ "$args" != "-" ] && read -r -a extra <<<"$args"
  label="$path${extra[*]:+ ${extra[*]}}"
  json=()
  [ "$code" = 0 ] && json=(--json -)
  timeout -k 2 10 "$exe" info "$path" "${extra[@]}" "${json[@]}" >"$tmp/out" 2>"$tmp/err"
  rc=$?
  why=""
  nlines=$(wc -l <"$tmp/err")
  if [ "$rc" = 124 ] || [ "$rc" = 137 ]; then
    why="timed out (10 s)"
  elif grep -qE 'Sanitizer|runtime error:|SUMMARY:|==[0-9]+==' "$tmp/err"; then
    why="sanitizer report: $(grep -m1 -E 'ERROR|runtime error' "$tmp/err")"
  elif [ "$rc" != "$code" ]; then
    why="exit $rc, expected $code: $(head -c 300 "$tmp/err")"
  elif [ "$code" != 0 ]; then
    msg=$(cat "$tmp/err")
    name=$(basename "$path")
    if [ "$nlines" != 1 ] || [ -n "$(tail -c1 "$tmp/err")" ]; then
      why="stderr is $nlines lines, expected one: $(head -c 300 "$tmp/err")"
    elif [[ $msg != *"$name"* ]]; then
      why="message does not name $name: $msg"
    else
      IFS='|' read -r -a subs <<<"$expect"
      for s in "${subs[@]}"; do
        if [[ $msg != *"$s"* ]]; then
          why="message lacks '$s': $msg"
          break
        fi
      done
    fi
  else
    if [ -s "$tmp/err" ]; then
      why="stderr not empty: $(head -c 300 "$tmp/err")"
    elif [ "$expect" != "-" ]; then
      IFS='|' read -r -a checks <<<"$expect"
      for c in "${checks[@]}"; do
        case $c in
          triangles=*)
            got=$(grep -oE '"triangles": *[0-9]+' "$tmp/out" | grep -oE '[0-9]+$')
            [ "$got" = "${c#triangles=}" ] || { why="triangles $got, expected ${c#triangles=}"; break; }
            ;;
          has=*)
            grep -qF -- "${c#has=}" "$tmp/out" || { why="info --json lacks '${c#has=}'"; break; }
            ;;
          warn=*)
            # Warnings are JSON strings; compare with the same escaping.
            want=$(printf '%s' "${c#warn=}" | sed 's/\\/\\\\/g; s/"/\\"/g')
            grep -qF -- "$want" "$tmp/out" || { why="no warning containing '${c#warn=}'"; break; }
            ;;
          *) why="bad check '$c' in expected.tsv"; break ;;
        esac
      done
    fi
  fi
  if [ -z "$why" ]; then
    pass=$((pass + 1))
    if [ "$code" = 0 ]; then
      echo "ok    $label"
    else
      echo "ok    $label: $(cat "$tmp/err" | sed 's/^photonbridge info: error: //')"
    fi
  else
    fail=$((fail + 1))
    failed_names+=("$label")
    echo "FAIL  $label: $why"
  fi
done <"$manifest"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ] && [ "$pass" -gt 0 ]
