# Malformed input, through the real binary: exit 2 (3 for a version or variant this build cannot
# read), one line on stderr naming the tool and the file and saying where and what is wrong.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples
W=$WORK

# check CODE CAUSE FILE: splat-info on FILE exits CODE with one line on stderr,
# "splat-info: FILE: ...CAUSE", CAUSE an extended regex saying where and what is wrong.
check() {
  expect_exit "$1" "$BIN/splat-info" "$3"
  expect_stderr "^splat-info: $(printf '%s' "$3" | sed 's/[][\.*^$+?(){}|]/\\&/g'): (.*: )?$2"
}

ply_header='ply\nformat binary_little_endian 1.0\nelement vertex %s\nproperty float x\nproperty float y\nproperty float z\nend_header\n'

# PLY
printf "$ply_header" 2 > $W/trunc.ply; head -c 20 /dev/zero >> $W/trunc.ply
check 2 "element 'vertex': 2 rows need at least 24 bytes but only 20 follow the header" $W/trunc.ply
printf "$ply_header" -5 > $W/badcount.ply
check 2 "line 3: element 'vertex': count '-5' is negative" $W/badcount.ply
printf "$ply_header" 99999999999 > $W/bigcount.ply; head -c 24 /dev/zero >> $W/bigcount.ply
check 2 "99999999999 rows need at least 1199999999988 bytes but only 24 follow the header" $W/bigcount.ply
printf "$ply_header" 1 > $W/nan.ply; printf '\x00\x00\xc0\x7f\x00\x00\x00\x00\x00\x00\x00\x00' >> $W/nan.ply
check 2 "byte 115: element 'vertex' row 0: NaN or infinite coordinate" $W/nan.ply
printf "$ply_header" 1 > $W/trail.ply; head -c 12 /dev/zero >> $W/trail.ply; printf 'junk' >> $W/trail.ply
check 2 "byte 127: trailing garbage after the last element \\(4 bytes\\)" $W/trail.ply
printf 'ply\nformat binary_little_endian 2.0\nelement vertex 0\nend_header\n' > $W/version.ply
check 2 "line 2: unknown PLY version '2.0'" $W/version.ply

# .splk: bad checksum (flip a payload byte of the sample), truncation, unknown major version,
# trailing garbage.
"$BIN/splat-convert" -q "$S/torus-ascii.ply" $W/good.splk
size=$(stat -c %s $W/good.splk)
cp $W/good.splk $W/crc.splk
printf '\x55' | dd of=$W/crc.splk bs=1 seek=$((size - 100)) conv=notrunc status=none
check 2 "chunk 'SPLT' at byte [0-9]+: checksum mismatch" $W/crc.splk
head -c $((size - 30)) $W/good.splk > $W/trunc.splk
check 2 "chunk 'SPLT': payload truncated: [0-9]+ bytes declared, only [0-9]+ left" $W/trunc.splk
cp $W/good.splk $W/trail.splk; printf 'x' >> $W/trail.splk
check 2 "byte $size: 1 bytes of trailing data after the END chunk" $W/trail.splk
cp $W/good.splk $W/major.splk
printf '\x63\x00' | dd of=$W/major.splk bs=1 seek=8 conv=notrunc status=none
check 3 "\\.splk version 99\\.0 is not supported" $W/major.splk

# XYZ: not a number, NaN, wrong column count, each with its line number.
printf '0 0 0\n1 2 zz\n' > $W/nan1.xyz
check 2 "line 2: column 3 \\(z\\): not a number: 'zz'" $W/nan1.xyz
printf '0 0 0\n1 nan 2\n' > $W/nan2.xyz
check 2 "line 2: NaN or infinite coordinate in column 2" $W/nan2.xyz
printf '0 0 0\n1 2\n' > $W/cols.xyz
check 2 "line 2: expected 3 columns, found 2" $W/cols.xyz

# OFF: counts larger than the file.
printf 'OFF\n1000000000 0 0\n0 0 0\n' > $W/big.off
check 2 "line 2: header claims 1000000000 vertices and 0 faces, more than the 6 bytes left" $W/big.off

# LAS: truncated points, unsupported point format (exit 3).
head -c 500 "$S/torus-las12.las" > $W/trunc.las
check 2 "header says [0-9]+ points of [0-9]+ bytes but only [0-9]+ bytes follow the point data offset" $W/trunc.las
cp "$S/torus-las12.las" $W/fmt.las
printf '\x09' | dd of=$W/fmt.las bs=1 seek=104 conv=notrunc status=none
check 3 "LAS point data format 9 .*is not supported" $W/fmt.las

# PCD: more points than bytes.
printf 'VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1000\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1000\nDATA binary\n' > $W/short.pcd
head -c 24 /dev/zero >> $W/short.pcd
check 2 "binary data truncated: 12000 bytes expected, 24 left" $W/short.pcd

# .spt: truncated entries, a damaged byte (checksum), a newer version (exit 3), unknown flags.
spt=$SRC/tests/fuzz/corpus/spt/sphere30.spt
head -c 500 "$spt" > $W/trunc.spt
check 2 "byte 24: [0-9]+ entries need more than the 372 bytes after the header \\(truncated file\\?\\)" $W/trunc.spt
cp "$spt" $W/flip.spt
printf '\x55' | dd of=$W/flip.spt bs=1 seek=300 conv=notrunc status=none
check 2 "byte 124: checksum mismatch" $W/flip.spt
cp "$spt" $W/version.spt
printf '\x09' | dd of=$W/version.spt bs=1 seek=8 conv=notrunc status=none
check 3 "byte 8: .spt version 9 is newer than this reader" $W/version.spt
cp "$spt" $W/flags.spt
printf '\x10' | dd of=$W/flags.spt bs=1 seek=12 conv=notrunc status=none
check 3 "byte 12: unknown flag bits 16" $W/flags.spt

finish
