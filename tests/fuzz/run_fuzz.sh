#!/usr/bin/env bash
# Builds the readers' libFuzzer target with clang (address and undefined-behaviour sanitizers; line
# tables only, which a crash's stack needs; -O0: 33 s of compiling on one core against 65 s at -O1,
# and 5000 inputs take 33 s either way, the target's file writes being most of it)
# and runs it for a bounded number of inputs, seeded with real LIGGGHTS (and LAMMPS) output made
# here and the kept regression inputs (tests/fuzz/regressions: every input that ever crashed a reader).
# A crash leaves its input in WORK/crash-*: copy it into tests/fuzz/regressions.
# Usage: tests/fuzz/run_fuzz.sh GRANSTACK WORK [RUNS]
set -euo pipefail
gs=${1:?usage: $0 GRANSTACK WORK [RUNS]}
work=${2:?usage: $0 GRANSTACK WORK [RUNS]}
runs=${3:-20000}
src=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work" && mkdir -p "$work/corpus"
export TMPDIR=$work  # the target's scratch file, kept in the work folder
clang++ -std=c++20 -O0 -gline-tables-only -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  -I"$src/formats/include" -I"$src/model/include" -I"$src/os/include" \
  "$src/tests/fuzz/fuzz_readers.cpp" "$src"/formats/src/{error,files,byte_source,line_reader,dump,text_dump_reader,repeated_tokens,binary_dump_reader,dump_writer,batches,series,data_file,digest}.cpp \
  "$src/os/src/interrupt.cpp" "$src/os/src/workers.cpp" -lfmt -lz -lzstd -lxxhash -lcrypto -o "$work/fuzz_readers"
# Seeds: a small real case, text and binary, plus its series and data file.
for format in text binary; do
  "$gs" generate -o "$work/case_$format" --blocks 1 --rows 2 --duration 2e-6 --dump-every 8 --dump-format "$format" >/dev/null
  "$gs" run "$work/case_$format" >/dev/null
done
cp "$work/case_text/dumps/dump.txt" "$work/case_binary/dumps/dump.bin" "$work/case_text/ke_series.txt" \
  "$work/case_text/data.stack" "$work/corpus/"
# LAMMPS's own binary form (its DUMPCUSTOM tag and column names), where LAMMPS is installed.
if command -v lmp >/dev/null; then
  "$gs" run --engine lammps --force "$work/case_binary" >/dev/null
  cp "$work/case_binary/dumps/dump.bin" "$work/corpus/dump_lammps.bin"
fi
gzip -c "$work/case_text/dumps/dump.txt" > "$work/corpus/dump.txt.gz"
# refsim writes its binary dumps as zstd streams: one among the seeds.
zstd -q -c "$work/case_binary/dumps/dump.bin" > "$work/corpus/dump.bin.zst"
cp "$src"/tests/fuzz/regressions/* "$work/corpus/" 2>/dev/null || true
# The regressions first, each on its own, then the bounded search.
for input in "$src"/tests/fuzz/regressions/*; do
  [ -f "$input" ] && "$work/fuzz_readers" "$input" >/dev/null 2>&1 || { [ -f "$input" ] && { echo "regression $input fails"; exit 1; }; }
done
cd "$work"
./fuzz_readers -runs="$runs" -max_total_time=90 -max_len=4096 -timeout=10 -rss_limit_mb=1024 corpus 2>&1 | tail -n 3
echo "fuzz: up to $runs inputs (90 s at most), no crash"
