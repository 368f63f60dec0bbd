// The entropy coder of LASzip ([Isenburg13], docs/references.md): Said's FastAC range coder
// ([Said04]; 32-bit interval, adaptive models with periodic updates), the adaptive bit and symbol
// models, and the integer compressor that codes a corrector against a prediction. Decoder and encoder give
// bit-exact LASzip streams. Spec: formats/laz.md.
//
// Safe for untrusted input: the decoder reads from a byte range and throws LazDataError when it
// needs a byte past its end. Encoders (LASzip, laz-perf, this one) end a stream with the zero
// bytes that the decoder's 4-byte look-ahead reads, so a valid stream never needs more.
#pragma once

#include <bit>
#include <cstddef>
#include <cstring>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

// The decoder's hot functions are inlined into the item decoders (they are, in turn, into the
// chunk's loop), so that the decoder's state stays in registers across a point's symbols instead
// of going through memory at every call.
#if defined(__GNUC__)
#define SPLATKIT_LAZ_INLINE [[gnu::always_inline]] inline
#else
#define SPLATKIT_LAZ_INLINE inline
#endif

namespace splatkit::laz {

// Thrown when a chunk's compressed bytes run out or cannot come from an encoder (the caller names
// the file and the chunk).
struct LazDataError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline constexpr uint32_t kMinLength = 0x01000000u, kMaxLength = 0xFFFFFFFFu;
inline constexpr int kBitLengthShift = 13, kSymLengthShift = 15;
inline constexpr uint32_t kBitMaxCount = 1u << kBitLengthShift, kSymMaxCount = 1u << kSymLengthShift;
// Decoder look-up table: 2^8 buckets (more for over 1024 symbols). At most 2^9: a valid value
// can exceed 2^15 by up to 63 after the length's shift, which must not leave the table.
inline constexpr uint32_t kDecoderTableBits = 8;

// Adaptive binary model.
struct BitModel {
  uint32_t bit_0_count = 1, bit_count = 2, bit_0_prob = 1u << (kBitLengthShift - 1);
  uint32_t update_cycle = 4, bits_until_update = 4;

  void update() {
    if ((bit_count += update_cycle) > kBitMaxCount) {
      bit_count = (bit_count + 1) >> 1;
      bit_0_count = (bit_0_count + 1) >> 1;
      if (bit_0_count == bit_count) ++bit_count;
    }
    const uint32_t scale = 0x80000000u / bit_count;
    bit_0_prob = (bit_0_count * scale) >> (31 - kBitLengthShift);
    update_cycle = (5 * update_cycle) >> 2;
    if (update_cycle > 64) update_cycle = 64;
    bits_until_update = update_cycle;
  }
};

// Adaptive model of `symbols` symbols (2..2048), with the decoder's look-up table above 16
// symbols (its size, ours to choose, does not change what is decoded). Its
// distribution, counts and table sit in one allocation (fewer cache lines per symbol).
class SymbolModel {
 public:
  explicit SymbolModel(uint32_t symbols) : symbols_(symbols), last_symbol_(symbols - 1) {
    if (symbols > 16) {
      // The table only narrows the decoder's search (the symbol is the one whose interval holds
      // the value, whatever the table), so its size is ours to choose: finer than LASzip's (2^3
      // to 2^9 buckets), most look-ups land on one symbol without bisection.
      uint32_t table_bits = kDecoderTableBits;
      while (symbols > (1u << (table_bits + 2))) ++table_bits;
      table_size_ = 1u << table_bits;
      table_shift_ = kSymLengthShift - table_bits;
    }
    storage_.assign(2 * std::size_t{symbols}, 0);
    distribution_ = storage_.data();
    symbol_count_ = distribution_ + symbols;
    // 16-bit entries (symbols < 2^11): half the cache lines.
    if (table_size_) table_.assign(table_size_ + 2, 0);
    decoder_table_ = table_size_ ? table_.data() : nullptr;
    for (uint32_t k = 0; k < symbols; ++k) symbol_count_[k] = 1;
    update_cycle_ = symbols;
    update();
    symbols_until_update_ = update_cycle_ = (symbols + 6) >> 1;
  }
  // Moves keep the heap block and so the pointers into it; copies would not.
  SymbolModel(SymbolModel&&) noexcept = default;
  SymbolModel& operator=(SymbolModel&&) noexcept = default;
  SymbolModel(const SymbolModel&) = delete;
  SymbolModel& operator=(const SymbolModel&) = delete;

  void update() {
    if ((total_count_ += update_cycle_) > kSymMaxCount) {
      total_count_ = 0;
      for (uint32_t n = 0; n < symbols_; ++n)
        total_count_ += (symbol_count_[n] = (symbol_count_[n] + 1) >> 1);
    }
    uint32_t sum = 0, s = 0;
    const uint32_t scale = 0x80000000u / total_count_;
    if (table_size_ == 0) {
      for (uint32_t k = 0; k < symbols_; ++k) {
        distribution_[k] = (scale * sum) >> (31 - kSymLengthShift);
        sum += symbol_count_[k];
      }
    } else {
      for (uint32_t k = 0; k < symbols_; ++k) {
        distribution_[k] = (scale * sum) >> (31 - kSymLengthShift);
        sum += symbol_count_[k];
        const uint32_t w = distribution_[k] >> table_shift_;
        while (s < w) decoder_table_[++s] = static_cast<uint16_t>(k - 1);
      }
      decoder_table_[0] = 0;
      while (s <= table_size_) decoder_table_[++s] = static_cast<uint16_t>(symbols_ - 1);
    }
    update_cycle_ = (5 * update_cycle_) >> 2;
    const uint32_t max_cycle = (symbols_ + 6) << 3;
    if (update_cycle_ > max_cycle) update_cycle_ = max_cycle;
    symbols_until_update_ = update_cycle_;
  }

  uint32_t symbols_, last_symbol_;
  uint32_t table_size_ = 0, table_shift_ = 0;
  uint32_t total_count_ = 0, update_cycle_ = 0, symbols_until_update_ = 0;
  std::vector<uint32_t> storage_;
  std::vector<uint16_t> table_;
  uint32_t* distribution_ = nullptr;
  uint32_t* symbol_count_ = nullptr;
  uint16_t* decoder_table_ = nullptr;
};

class ArithmeticDecoder {
 public:
  ArithmeticDecoder(const unsigned char* begin, const unsigned char* end) : p_(begin), end_(end) {}

  // Reads the 4 bytes that start a stream.
  void init() {
    length_ = kMaxLength;
    value_ = static_cast<uint32_t>(get_byte()) << 24;
    value_ |= static_cast<uint32_t>(get_byte()) << 16;
    value_ |= static_cast<uint32_t>(get_byte()) << 8;
    value_ |= static_cast<uint32_t>(get_byte());
  }

  SPLATKIT_LAZ_INLINE uint32_t decode_bit(BitModel& m) {
    const uint32_t x = m.bit_0_prob * (length_ >> kBitLengthShift);
    const uint32_t sym = value_ >= x;
    if (sym == 0) {
      length_ = x;
      ++m.bit_0_count;
    } else {
      value_ -= x;
      length_ -= x;
    }
    renormalize_if_short();
    if (--m.bits_until_update == 0) m.update();
    return sym;
  }

  SPLATKIT_LAZ_INLINE uint32_t decode_symbol(SymbolModel& m) {
    uint32_t n, sym, x, y = length_;
    if (m.table_size_) {
      const uint32_t dv = value_ / (length_ >>= kSymLengthShift);
      const uint32_t t = dv >> m.table_shift_;
      // Only a corrupt stream gets value >= length, which would index past the table.
      if (t > m.table_size_) throw LazDataError("corrupt compressed data");
      sym = m.decoder_table_[t];
      n = m.decoder_table_[t + 1] + 1;
      while (n > sym + 1) {
        const uint32_t k = (sym + n) >> 1;
        if (m.distribution_[k] > dv) n = k;
        else sym = k;
      }
      x = m.distribution_[sym] * length_;
      if (sym != m.last_symbol_) y = m.distribution_[sym + 1] * length_;
    } else {
      x = sym = 0;
      length_ >>= kSymLengthShift;
      uint32_t k = (n = m.symbols_) >> 1;
      do {
        const uint32_t z = length_ * m.distribution_[k];
        if (z > value_) {
          n = k;
          y = z;
        } else {
          sym = k;
          x = z;
        }
      } while ((k = (sym + n) >> 1) != sym);
    }
    value_ -= x;
    length_ = y - x;
    renormalize_if_short();
    ++m.symbol_count_[sym];
    if (--m.symbols_until_update_ == 0) m.update();
    return sym;
  }

  // `bits` raw bits (1..32).
  SPLATKIT_LAZ_INLINE uint32_t read_bits(uint32_t bits) {
    if (bits > 19) {
      const uint32_t low = read_short();
      return (read_few_bits(bits - 16) << 16) | low;
    }
    return read_few_bits(bits);
  }
  SPLATKIT_LAZ_INLINE uint32_t read_short() {
    const uint32_t sym = value_ / (length_ >>= 16);
    value_ -= length_ * sym;
    renormalize_if_short();
    return sym & 0xFFFF;  // a corrupt stream can exceed 16 bits; a valid one never does
  }
  uint32_t read_int() {
    const uint32_t low = read_short();
    return (read_short() << 16) | low;
  }

  // `bits` raw bits (1..19).
  SPLATKIT_LAZ_INLINE uint32_t read_few_bits(uint32_t bits) {
    const uint32_t sym = value_ / (length_ >>= bits);
    value_ -= length_ * sym;
    renormalize_if_short();
    return sym & ((1u << bits) - 1);  // a corrupt stream can exceed `bits`; a valid one never does
  }

  // Where the decoder stands in its byte range (bytes consumed, including look-ahead).
  const unsigned char* position() const { return p_; }

 private:
  SPLATKIT_LAZ_INLINE unsigned char get_byte() {
    if (p_ < end_) return *p_++;
    throw LazDataError("compressed data ends before the points it should hold");
  }
  SPLATKIT_LAZ_INLINE void renormalize() {
    do {
      value_ = (value_ << 8) | get_byte();
    } while ((length_ <<= 8) < kMinLength);
  }
  // renormalize() when the interval is below kMinLength, without a branch on it (whether a
  // symbol needs bytes, and how many, is as good as random): n = leading zero bits / 8 bytes
  // (0 to 3) shifted in from a 4-byte load, the same state as renormalize()'s loop; near the end
  // of the bytes (fewer than 4 left), or for an empty interval (a corrupt stream), the loop.
  SPLATKIT_LAZ_INLINE void renormalize_if_short() {
    const uint32_t n = static_cast<uint32_t>(std::countl_zero(length_)) >> 3;
    if (n <= 3 && end_ - p_ >= 4) [[likely]] {
      uint32_t next;
      std::memcpy(&next, p_, 4);
      next = __builtin_bswap32(next);  // the stream's bytes, first one highest
      value_ = static_cast<uint32_t>(((uint64_t{value_} << 32) | next) >> (32 - 8 * n));
      length_ <<= 8 * n;
      p_ += n;
    } else if (length_ < kMinLength) {
      renormalize();
    }
  }

  const unsigned char* p_;
  const unsigned char* end_;
  uint32_t value_ = 0, length_ = kMaxLength;
};

class ArithmeticEncoder {
 public:
  explicit ArithmeticEncoder(std::vector<unsigned char>& out) : out_(out) {}

  void encode_bit(BitModel& m, uint32_t sym) {
    const uint32_t x = m.bit_0_prob * (length_ >> kBitLengthShift);
    if (sym == 0) {
      length_ = x;
      ++m.bit_0_count;
    } else {
      const uint32_t init_base = base_;
      base_ += x;
      length_ -= x;
      if (init_base > base_) propagate_carry();
    }
    if (length_ < kMinLength) renormalize();
    if (--m.bits_until_update == 0) m.update();
  }

  void encode_symbol(SymbolModel& m, uint32_t sym) {
    const uint32_t init_base = base_;
    uint32_t x;
    if (sym == m.last_symbol_) {
      x = m.distribution_[sym] * (length_ >> kSymLengthShift);
      base_ += x;
      length_ -= x;
    } else {
      x = m.distribution_[sym] * (length_ >>= kSymLengthShift);
      base_ += x;
      length_ = m.distribution_[sym + 1] * length_ - x;
    }
    if (init_base > base_) propagate_carry();
    if (length_ < kMinLength) renormalize();
    ++m.symbol_count_[sym];
    if (--m.symbols_until_update_ == 0) m.update();
  }

  void write_bits(uint32_t bits, uint32_t sym) {
    if (bits > 19) {
      write_short(sym & 0xFFFF);
      sym >>= 16;
      bits -= 16;
    }
    const uint32_t init_base = base_;
    base_ += sym * (length_ >>= bits);
    if (init_base > base_) propagate_carry();
    if (length_ < kMinLength) renormalize();
  }
  void write_short(uint32_t sym) {
    const uint32_t init_base = base_;
    base_ += sym * (length_ >>= 16);
    if (init_base > base_) propagate_carry();
    if (length_ < kMinLength) renormalize();
  }
  void write_int(uint32_t sym) {
    write_short(sym & 0xFFFF);
    write_short(sym >> 16);
  }

  // Emits the final bytes, then zero bytes up to exactly what a decoder reads: it looks ahead
  // 4 bytes, and decoders that read chunks one after the other (laz-perf) need the next chunk to
  // start where the last one's decoder stopped.
  void done() {
    const uint32_t init_base = base_;
    const bool one_byte = length_ > 2 * kMinLength;
    if (one_byte) {
      base_ += kMinLength;
      length_ = kMinLength >> 1;
    } else {
      base_ += kMinLength >> 1;
      length_ = kMinLength >> 9;
    }
    if (init_base > base_) propagate_carry();
    renormalize();
    out_.insert(out_.end(), one_byte ? 3 : 2, 0);
  }

 private:
  void propagate_carry() {
    std::size_t i = out_.size();
    while (i > 0 && out_[i - 1] == 0xFF) out_[--i] = 0;
    if (i > 0) ++out_[i - 1];
  }
  void renormalize() {
    do {
      out_.push_back(static_cast<unsigned char>(base_ >> 24));
      base_ <<= 8;
    } while ((length_ <<= 8) < kMinLength);
  }

  std::vector<unsigned char>& out_;
  uint32_t base_ = 0, length_ = kMaxLength;
};

// LASzip's integer compressor: codes `real` against a prediction as a corrector c, first the
// number k of bits of c (one model per context), then c within its 2^k interval (one model per k
// for the top bits_high bits, the rest raw). Arithmetic wraps modulo 2^bits.
class IntegerCompressor {
 public:
  IntegerCompressor(uint32_t bits, uint32_t contexts, uint32_t bits_high = 8)
      : bits_high_(bits_high) {
    if (bits && bits < 32) {
      corr_bits_ = bits;
      corr_range_ = 1u << bits;
      corr_min_ = -static_cast<int32_t>(corr_range_ / 2);
      corr_max_ = corr_min_ + static_cast<int32_t>(corr_range_ - 1);
    } else {
      corr_bits_ = 32;
      corr_range_ = 0;
      corr_min_ = INT32_MIN;
      corr_max_ = INT32_MAX;
    }
    m_bits_.reserve(contexts);
    for (uint32_t i = 0; i < contexts; ++i) m_bits_.emplace_back(corr_bits_ + 1);
    m_corrector_.reserve(corr_bits_ + 1);
    m_corrector_.emplace_back(2);  // slot 0 unused: k = 0 codes with the bit model
    for (uint32_t i = 1; i <= corr_bits_; ++i)
      m_corrector_.emplace_back(1u << (i <= bits_high_ ? i : bits_high_));
  }

  uint32_t k() const { return k_; }

  SPLATKIT_LAZ_INLINE int32_t decompress(ArithmeticDecoder& dec, int32_t pred, uint32_t context) {
    uint32_t real = static_cast<uint32_t>(pred) + static_cast<uint32_t>(read_corrector(dec, context));
    if (corr_range_) {
      if (static_cast<int32_t>(real) < 0) real += corr_range_;
      else if (real >= corr_range_) real -= corr_range_;
    }
    return static_cast<int32_t>(real);
  }

  void compress(ArithmeticEncoder& enc, int32_t pred, int32_t real, uint32_t context) {
    int64_t corr = static_cast<int64_t>(real) - pred;
    if (corr_range_) {
      if (corr < corr_min_) corr += corr_range_;
      else if (corr > corr_max_) corr -= corr_range_;
    } else {
      corr = static_cast<int32_t>(static_cast<uint32_t>(corr));
    }
    write_corrector(enc, static_cast<int32_t>(corr), context);
  }

 private:
  SPLATKIT_LAZ_INLINE int32_t read_corrector(ArithmeticDecoder& dec, uint32_t context) {
    k_ = dec.decode_symbol(m_bits_[context]);
    if (k_ == 0) return static_cast<int32_t>(dec.decode_bit(bit0_));
    int64_t c;
    if (k_ <= bits_high_) {
      c = dec.decode_symbol(m_corrector_[k_]);
    } else {
      const uint32_t k1 = k_ - bits_high_;
      const uint64_t high = dec.decode_symbol(m_corrector_[k_]);
      c = static_cast<int64_t>((high << k1) | dec.read_bits(k1));
    }
    if (c >= (int64_t{1} << (k_ - 1))) c += 1;
    else c -= (int64_t{1} << k_) - 1;
    return static_cast<int32_t>(static_cast<uint32_t>(c));
  }

  void write_corrector(ArithmeticEncoder& enc, int32_t c, uint32_t context) {
    uint32_t c1 = c <= 0 ? 0u - static_cast<uint32_t>(c) : static_cast<uint32_t>(c) - 1;
    k_ = 0;
    while (c1) {
      c1 >>= 1;
      ++k_;
    }
    enc.encode_symbol(m_bits_[context], k_);
    if (k_ == 0) {
      enc.encode_bit(bit0_, static_cast<uint32_t>(c));
      return;
    }
    uint64_t u = c < 0 ? static_cast<uint64_t>(static_cast<int64_t>(c) + ((int64_t{1} << k_) - 1))
                       : static_cast<uint64_t>(c) - 1;
    if (k_ <= bits_high_) {
      enc.encode_symbol(m_corrector_[k_], static_cast<uint32_t>(u));
    } else {
      const uint32_t k1 = k_ - bits_high_;
      const uint32_t low = static_cast<uint32_t>(u & ((uint64_t{1} << k1) - 1));
      enc.encode_symbol(m_corrector_[k_], static_cast<uint32_t>(u >> k1));
      enc.write_bits(k1, low);
    }
  }

  uint32_t bits_high_, corr_bits_ = 0, corr_range_ = 0;
  int32_t corr_min_ = 0, corr_max_ = 0;
  uint32_t k_ = 0;
  std::vector<SymbolModel> m_bits_;
  BitModel bit0_;
  std::vector<SymbolModel> m_corrector_;
};

}  // namespace splatkit::laz
