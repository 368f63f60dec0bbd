// LASzip's GPS time model ([Isenburg13]; formats/laz.md): up to four interleaved time sequences,
// each predicted by its last difference times a small multiplier, as GPSTIME11 version 2 (point
// formats 1 and 3) and POINT14 version 3 (formats 6-8) code it. Version 3 never sees a repeated
// time (POINT14's change bits say so) and has no code for one; its other codes are those of
// version 2 less one.
//
// Safe for untrusted input: a corrupt stream throws LazDataError.
#pragma once

#include <array>
#include <cstdint>

#include "formats/laz_arithmetic.h"
#include "formats/laz_models.h"

namespace splatkit::laz {

// kRepeatCode: version 2's model (a repeated time has its own code), else version 3's.
template <bool kRepeatCode>
class GpsTimeModel {
 public:
  // A fresh model takes the chunk's first time (stored raw) before coding the next ones.
  void set_first(int64_t t) { last_time_[0] = t; }

  int64_t decode(ArithmeticDecoder& dec) {
    // Each switch to another sequence is followed by a value in it; an encoder never switches
    // twice in a row, so a few rounds bound a corrupt stream.
    for (int round = 0;; ++round) {
      if (round == 4) throw LazDataError("corrupt GPS time stream");
      if (last_diff_[last_] == 0) {
        const uint32_t code = dec.decode_symbol(zero_diff_);
        if (code == kZeroDiffFits) {
          last_diff_[last_] = ic_.decompress(dec, 0, 0);
          last_time_[last_] += last_diff_[last_];
          extreme_[last_] = 0;
        } else if (code == kZeroDiffFits + 1) {
          read_full(dec);
        } else if (code > kZeroDiffFits + 1) {
          last_ = (last_ + code - (kZeroDiffFits + 1)) & 3;
          continue;
        }  // else the repeat code (version 2): the same time
      } else {
        const uint32_t multi = dec.decode_symbol(multi_);
        if (multi == 1) {
          last_time_[last_] += ic_.decompress(dec, last_diff_[last_], 1);
          extreme_[last_] = 0;
        } else if (multi < kCodeRepeat) {
          last_time_[last_] += decode_multiple(dec, multi);
        } else if (multi == kCodeFull) {
          read_full(dec);
        } else if (multi > kCodeFull) {
          last_ = (last_ + multi - kCodeFull) & 3;
          continue;
        }  // else the repeat code (version 2): the same time
      }
      return last_time_[last_];
    }
  }

  void encode(ArithmeticEncoder& enc, int64_t t) {
    for (;;) {
      if constexpr (kRepeatCode) {
        if (t == last_time_[last_]) {
          enc.encode_symbol(last_diff_[last_] == 0 ? zero_diff_ : multi_,
                            last_diff_[last_] == 0 ? 0 : kCodeRepeat);
          return;
        }
      }
      const int64_t d64 =
          static_cast<int64_t>(static_cast<uint64_t>(t) - static_cast<uint64_t>(last_time_[last_]));
      const bool fits = d64 == static_cast<int32_t>(d64);
      const int32_t diff = static_cast<int32_t>(d64);
      if (last_diff_[last_] == 0) {
        if (fits) {
          enc.encode_symbol(zero_diff_, kZeroDiffFits);
          ic_.compress(enc, 0, diff, 0);
          last_diff_[last_] = diff;
          extreme_[last_] = 0;
          last_time_[last_] = t;
          return;
        }
        if (const unsigned other = other_sequence(t)) {
          enc.encode_symbol(zero_diff_, kZeroDiffFits + 1 + other);
          last_ = (last_ + other) & 3;
          continue;
        }
        enc.encode_symbol(zero_diff_, kZeroDiffFits + 1);
        write_full(enc, t);
        return;
      }
      if (fits) {
        encode_multiple(enc, diff);
        last_time_[last_] = t;
        return;
      }
      if (const unsigned other = other_sequence(t)) {
        enc.encode_symbol(multi_, kCodeFull + other);
        last_ = (last_ + other) & 3;
        continue;
      }
      enc.encode_symbol(multi_, kCodeFull);
      write_full(enc, t);
      return;
    }
  }

 private:
  static constexpr int32_t kMulti = 500, kMultiMinus = -10;
  static constexpr uint32_t kRepeat = kRepeatCode ? 1 : 0;
  // Codes after the last diff was zero: [repeat,] fits in 32 bits, full, switch by 1..3.
  static constexpr uint32_t kZeroDiffFits = kRepeat;
  // Codes otherwise: 0..kMulti - kMultiMinus multiples of the last diff, [repeat,] full, switch.
  static constexpr uint32_t kCodeRepeat = kMulti - kMultiMinus + 1;
  static constexpr uint32_t kCodeFull = kCodeRepeat + kRepeat;

  // A difference coded as a multiple `multi` (0 < multi < kCodeRepeat, 1 aside) of the last one.
  int32_t decode_multiple(ArithmeticDecoder& dec, uint32_t multi) {
    int32_t diff;
    if (multi == 0) {
      diff = ic_.decompress(dec, 0, 7);
      count_extreme(diff);
    } else if (multi < static_cast<uint32_t>(kMulti)) {
      diff = ic_.decompress(dec, wrap_mul(static_cast<int32_t>(multi), last_diff_[last_]),
                            multi < 10 ? 2 : 3);
    } else if (multi == static_cast<uint32_t>(kMulti)) {
      diff = ic_.decompress(dec, wrap_mul(kMulti, last_diff_[last_]), 4);
      count_extreme(diff);
    } else {
      const int32_t neg = kMulti - static_cast<int32_t>(multi);
      if (neg > kMultiMinus) {
        diff = ic_.decompress(dec, wrap_mul(neg, last_diff_[last_]), 5);
      } else {
        diff = ic_.decompress(dec, wrap_mul(kMultiMinus, last_diff_[last_]), 6);
        count_extreme(diff);
      }
    }
    return diff;
  }

  void encode_multiple(ArithmeticEncoder& enc, int32_t diff) {
    const float multi_f = static_cast<float>(diff) / static_cast<float>(last_diff_[last_]);
    // LASzip's I32_QUANTIZE, with quotients beyond int range sent to the extreme codes.
    const int32_t multi = multi_f >= 1e6f    ? kMulti
                          : multi_f <= -1e6f ? kMultiMinus
                          : multi_f >= 0     ? static_cast<int32_t>(multi_f + 0.5f)
                                             : static_cast<int32_t>(multi_f - 0.5f);
    if (multi == 1) {
      enc.encode_symbol(multi_, 1);
      ic_.compress(enc, last_diff_[last_], diff, 1);
      extreme_[last_] = 0;
    } else if (multi > 0) {
      if (multi < kMulti) {
        enc.encode_symbol(multi_, static_cast<uint32_t>(multi));
        ic_.compress(enc, wrap_mul(multi, last_diff_[last_]), diff, multi < 10 ? 2 : 3);
      } else {
        enc.encode_symbol(multi_, kMulti);
        ic_.compress(enc, wrap_mul(kMulti, last_diff_[last_]), diff, 4);
        count_extreme(diff);
      }
    } else if (multi < 0) {
      if (multi > kMultiMinus) {
        enc.encode_symbol(multi_, static_cast<uint32_t>(kMulti - multi));
        ic_.compress(enc, wrap_mul(multi, last_diff_[last_]), diff, 5);
      } else {
        enc.encode_symbol(multi_, static_cast<uint32_t>(kMulti - kMultiMinus));
        ic_.compress(enc, wrap_mul(kMultiMinus, last_diff_[last_]), diff, 6);
        count_extreme(diff);
      }
    } else {
      enc.encode_symbol(multi_, 0);
      ic_.compress(enc, 0, diff, 7);
      count_extreme(diff);
    }
  }

  void count_extreme(int32_t diff) {
    if (++extreme_[last_] > 3) {
      last_diff_[last_] = diff;
      extreme_[last_] = 0;
    }
  }
  void read_full(ArithmeticDecoder& dec) {
    next_ = (next_ + 1) & 3;
    const uint64_t high = static_cast<uint32_t>(ic_.decompress(
        dec, static_cast<int32_t>(static_cast<uint64_t>(last_time_[last_]) >> 32), 8));
    last_time_[next_] = static_cast<int64_t>(high << 32 | dec.read_int());
    last_ = next_;
    last_diff_[last_] = 0;
    extreme_[last_] = 0;
  }
  void write_full(ArithmeticEncoder& enc, int64_t t) {
    const uint64_t u = static_cast<uint64_t>(t);
    ic_.compress(enc, static_cast<int32_t>(static_cast<uint64_t>(last_time_[last_]) >> 32),
                 static_cast<int32_t>(u >> 32), 8);
    enc.write_int(static_cast<uint32_t>(u));
    next_ = (next_ + 1) & 3;
    last_ = next_;
    last_diff_[last_] = 0;
    extreme_[last_] = 0;
    last_time_[last_] = t;
  }
  // 1..3 when t is within 32 bits of another sequence's last time, else 0.
  unsigned other_sequence(int64_t t) const {
    for (unsigned i = 1; i < 4; ++i) {
      const int64_t d = static_cast<int64_t>(static_cast<uint64_t>(t) -
                                             static_cast<uint64_t>(last_time_[(last_ + i) & 3]));
      if (d == static_cast<int32_t>(d)) return i;
    }
    return 0;
  }

  unsigned last_ = 0, next_ = 0;
  std::array<int64_t, 4> last_time_{};
  std::array<int32_t, 4> last_diff_{}, extreme_{};
  SymbolModel multi_{kCodeFull + 4}, zero_diff_{kZeroDiffFits + 5};
  IntegerCompressor ic_{32, 9};
};

}  // namespace splatkit::laz
