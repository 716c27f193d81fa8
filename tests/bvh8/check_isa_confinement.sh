#!/bin/sh
# Usage: check_isa_confinement.sh OBJDUMP MODE FILE [PATTERN]
# Disassembles FILE (archive or executable) and lists every function outside the namespaces
# thicket::bvh8_avx2 and thicket::bvh8_avx512 that contains a VEX/EVEX instruction (a v-prefixed
# AVX mnemonic, a ymm/zmm register, an AVX-512 mask register). Such a function is the dispatch
# trap: compiled for AVX, callable from baseline code, an illegal instruction on an older CPU.
# MODE clean: pass iff there is none. MODE clean-cli: the same for an executable, where the
# C library's own AVX variants (memcpy etc. behind IFUNC, in the dynamic libc, not here) cannot
# appear; MODE violation: pass iff there is at least one, and one whose name matches PATTERN
# (grep -E) when given (the check can fail).
set -eu
objdump=$1 mode=$2 file=$3 pattern=${4:-}
[ -f "$file" ] || { echo "no such file: $file"; exit 2; }
"$objdump" -d -C --no-show-raw-insn "$file" > "${TMPDIR:-/tmp}/bvh8-isa-$$.txt"
found=$(awk '
  /^[0-9a-f]+ <.*>:$/ {
    fn = substr($0, index($0, "<") + 1); sub(/>:$/, "", fn); flagged = 0; first = 1; skip = ""; next
  }
  /^ +[0-9a-f]+:\t/ {
    if (flagged) next
    addr = $1; sub(/:$/, "", addr)
    if (skip != "") { if (addr != skip) next; skip = "" }
    line = $0; sub(/^ +[0-9a-f]+:\t/, "", line)
    n = split(line, w, /[ \t]+/); m = w[1]
    # clang -fsanitize=function (UBSan) starts a function with "jmp +8" over 6 bytes of data (a
    # signature and a type hash) that objdump decodes as instructions, sometimes VEX ones: skip them.
    if (first) { first = 0; if (m == "jmp" && line ~ /\+0x8>$/) { skip = w[2]; next } }
    if (m == "rex" || m == "lock" || m == "rep" || m == "repz" || m == "repnz" || m == "notrack" || m == "bnd" || m == "data16" || m == "cs") m = w[2]
    vex = (m ~ /^v/ && m !~ /^(verr|verw|vm(call|clear|launch|ptrld|ptrst|read|resume|write|xoff|xon|func|run|load|save|mcall))$/)
    if (vex || line ~ /%[yz]mm[0-9]/ || line ~ /%k[0-7]/) {
      name = fn; gsub(/\(anonymous namespace\)/, "anon", name)
      # The qualified name: template arguments dropped (innermost first, so that a template
      # return type such as HitT<float> goes too), then the parameters, then the return type.
      head = name; while (gsub(/<[^<>]*>/, "", head)) {}; sub(/\(.*/, "", head); k = split(head, parts, " "); q = parts[k]
      if (q !~ /^thicket::bvh8_avx(2|512)::/) { print fn " :: " m; flagged = 1 }
    }
  }' "${TMPDIR:-/tmp}/bvh8-isa-$$.txt")
rm -f "${TMPDIR:-/tmp}/bvh8-isa-$$.txt"
count=$(printf '%s' "$found" | grep -c . || true)
case $mode in
  clean|clean-cli)
    if [ "$count" -ne 0 ]; then
      echo "FAIL: $count function(s) outside thicket::bvh8_avx2/avx512 hold AVX instructions:"
      printf '%s\n' "$found" | head -20; exit 1
    fi
    echo "OK: no AVX instruction outside thicket::bvh8_avx2/avx512 in $file" ;;
  violation)
    if [ "$count" -eq 0 ]; then echo "FAIL: the trap fixture was not flagged: the check cannot fail"; exit 1; fi
    if [ -n "$pattern" ] && ! printf '%s\n' "$found" | grep -Eq "$pattern"; then
      echo "FAIL: no flagged function matches '$pattern':"; printf '%s\n' "$found" | head -5; exit 1
    fi
    echo "OK: the check flags the trap fixture ($count function(s)):"; printf '%s\n' "$found" | head -5 ;;
  *) echo "unknown mode $mode"; exit 2 ;;
esac
