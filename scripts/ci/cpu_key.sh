#!/usr/bin/env bash
# The CPU as the instruction-count baselines name it: its model name, and a hash of the instruction-set extensions
# it reports (llvmpipe's JIT compiles for them: two hosts that both say "Intel(R) Xeon(R) Processor", one with
# AVX-512 FP16 and one without, count 10-16% apart per frame for the same build). Prints e.g.
# Intel-R-Xeon-R-Processor-isa3f9c02d1. Read by ci_compare.sh and refresh_baselines.sh.
set -euo pipefail
model="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | tr -cs 'A-Za-z0-9.' '-' | sed 's/^-//; s/-$//')"
isa="$(grep -m1 '^flags' /proc/cpuinfo | cut -d: -f2 | tr ' ' '\n' |
  grep -E '^(sse|ssse|avx|fma|f16c|bmi|popcnt|movbe|amx|vaes|vpclmul|gfni|sha|adx|abm|aes|pclmul|xsave)' |
  sort | tr '\n' ' ' | sha1sum | cut -c1-8)"
echo "$model-isa$isa"
