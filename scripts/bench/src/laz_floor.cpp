// What the range decoder's serial chain alone costs a LASzip decoder of point formats 0-3 on
// this machine, per point, without any point model (laz.sh prints it beside the decoders): an
// estimate of the least time a straightforward decoder needs, not a bound.
//
// A point-wise LASzip chunk ([Isenburg13], docs/references.md) is one arithmetic-coded stream:
// each symbol divides the current value by the interval length, looks the quotient up in the
// model's table, multiplies back, subtracts and renormalises, and the next symbol cannot start
// before that one has finished. A decoder that runs one chain per chunk (splatkit's, LASzip's,
// laz-perf's) takes at least (symbols per point) x (chain time per symbol) + (raw reads per
// point) x (chain time per read) per core. Two chunks' chains interleaved in one thread overlap
// their latencies (about 12 % less time per symbol in a test of the bare chains); layered
// chunks (formats 6-8) hold one stream per layer, so this does not describe them.
//
// Measured here on random bytes (every byte string is a valid stream), one thread:
//   table: the least work of a symbol of a model with a decoder table (256 symbols, a fixed
//          distribution of 3.6 bits per symbol, near the input's; no adaptation, no bisection
//          past the table's bucket);
//   raw:   a read of 2 raw bits (the input's raw reads average 2.3): a division, a
//          multiplication, renormalisation;
//   ours:  splatkit's ArithmeticDecoder::decode_symbol and read_bits on the same bytes, with an
//          adaptive 256-symbol model that starts from the fixed model's distribution (updates
//          included).
// usage: laz_floor [table symbols per point] [raw reads per point] [threads]
// (defaults: the counts of laz.sh's point format 2 input, see laz.sh)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "formats/laz_arithmetic.h"

namespace {

using Clock = std::chrono::steady_clock;

constexpr long kOps = 50'000'000;

std::vector<unsigned char> random_bytes() {
  std::vector<unsigned char> b(std::size_t{1} << 26);
  std::mt19937 rng(1);
  for (auto& x : b) x = static_cast<unsigned char>(rng());
  return b;
}

// The fixed model: 8 frequent symbols, the rest rare; returns the bits per symbol it codes.
double fixed_model(std::vector<uint32_t>& dist, std::vector<uint16_t>& table) {
  std::vector<double> p(256);
  double total = 0;
  for (int i = 0; i < 256; ++i) total += p[i] = i < 8 ? 120.0 : 0.25;
  double sum = 0, bits = 0;
  dist.assign(257, 0);
  for (int i = 0; i < 256; ++i) {
    dist[i] = static_cast<uint32_t>(sum / total * 32768);
    sum += p[i];
    bits -= p[i] / total * std::log2(p[i] / total);
  }
  dist[256] = 32768;
  table.assign(258, 0);
  for (int t = 0, s = 0; t < 258; ++t) {
    while (s < 255 && dist[s + 1] <= static_cast<uint32_t>(t) << 7) ++s;
    table[t] = static_cast<uint16_t>(s);
  }
  return bits;
}

// Times kOps operations of a bare range decoder over `bytes`: step(value, length) decodes one,
// updating both, and returns what it decoded; renormalisation follows it.
template <class Step>
double chain_ns(const std::vector<unsigned char>& bytes, uint64_t& sink, Step step) {
  const unsigned char* p = bytes.data() + 4;
  const unsigned char* wrap = bytes.data() + bytes.size() - 16;
  uint32_t value =
      uint32_t{bytes[0]} << 24 | uint32_t{bytes[1]} << 16 | uint32_t{bytes[2]} << 8 | bytes[3];
  uint32_t length = 0xFFFFFFFFu;
  const auto t0 = Clock::now();
  for (long i = 0; i < kOps; ++i) {
    const uint32_t s = step(value, length);
    while (length < 0x01000000u) {
      value = value << 8 | *p++;
      length <<= 8;
    }
    if (p > wrap) p = bytes.data() + 4;
    sink += s;
  }
  return std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / kOps;
}

double table_chain_ns(const std::vector<unsigned char>& bytes, uint64_t& sink) {
  std::vector<uint32_t> dist;
  std::vector<uint16_t> table;
  fixed_model(dist, table);
  return chain_ns(bytes, sink, [&](uint32_t& value, uint32_t& length) {
    const uint32_t l = length >> 15;
    const uint32_t dv = value / l;
    uint32_t s = table[dv >> 7];
    while (s < 255 && dist[s + 1] <= dv) ++s;
    const uint32_t x = dist[s] * l;
    const uint32_t y = s == 255 ? length : dist[s + 1] * l;
    value -= x;
    length = y - x;
    return s;
  });
}

double raw_chain_ns(const std::vector<unsigned char>& bytes, uint64_t& sink) {
  return chain_ns(bytes, sink, [](uint32_t& value, uint32_t& length) {
    length >>= 2;
    const uint32_t s = value / length;
    value -= length * s;
    return s;
  });
}

// splatkit's decoder on the same kind of stream: `raw` reads 2 raw bits, else an adaptive
// 256-symbol model decodes. Restarts on fresh bytes before the buffer ends.
double ours_ns(const std::vector<unsigned char>& bytes, bool raw, uint64_t& sink) {
  using splatkit::laz::ArithmeticDecoder;
  const long per_stream = 1'000'000;  // well within the buffer at up to 8 bits per operation
  double ns = 0;
  for (long done = 0; done < kOps; done += per_stream) {
    // The model starts from the fixed model's distribution (8 symbols 480 times as frequent as
    // the rest), so that it codes about as many bits per symbol; it adapts from there.
    splatkit::laz::SymbolModel model(256);
    uint32_t total = 0;
    for (uint32_t k = 0; k < 256; ++k) total += model.symbol_count_[k] = k < 8 ? 480 : 1;
    model.total_count_ = total - model.update_cycle_;
    model.update();
    const std::size_t at = static_cast<std::size_t>(done / per_stream % 8) * (bytes.size() / 8);
    ArithmeticDecoder dec(bytes.data() + at, bytes.data() + at + bytes.size() / 8);
    dec.init();
    const auto t0 = Clock::now();
    for (long i = 0; i < per_stream; ++i) sink += raw ? dec.read_bits(2) : dec.decode_symbol(model);
    ns += std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
  }
  return ns / kOps;
}

}  // namespace

int main(int argc, char** argv) {
  const double symbols = argc > 1 ? std::atof(argv[1]) : 15.84;
  const double raws = argc > 2 ? std::atof(argv[2]) : 3.52;
  const int threads = argc > 3 ? std::atoi(argv[3]) : 2;
  const auto bytes = random_bytes();
  std::vector<uint32_t> dist;
  std::vector<uint16_t> table;
  const double bits = fixed_model(dist, table);
  uint64_t sink = 0;
  double table_ns = 1e30, raw_ns = 1e30, ours_sym = 1e30, ours_raw = 1e30;
  for (int r = 0; r < 3; ++r) {  // the least of three: the machine may be shared
    table_ns = std::min(table_ns, table_chain_ns(bytes, sink));
    raw_ns = std::min(raw_ns, raw_chain_ns(bytes, sink));
    ours_sym = std::min(ours_sym, ours_ns(bytes, false, sink));
    ours_raw = std::min(ours_raw, ours_ns(bytes, true, sink));
  }
  const double floor_ns = symbols * table_ns + raws * raw_ns;
  const double ours_floor_ns = symbols * ours_sym + raws * ours_raw;
  std::printf(
      "range decoder chain alone, point formats 0-3 (1 thread, random bytes; checksum %llu):\n",
      static_cast<unsigned long long>(sink % 1000));
  std::printf(
      "  table symbol %.2f ns (fixed model, %.1f bits per symbol), raw read %.2f ns;"
      " splatkit's decode_symbol %.2f ns (adaptive), read_bits %.2f ns\n",
      table_ns, bits, raw_ns, ours_sym, ours_raw);
  std::printf(
      "chain alone at %.2f table symbols + %.2f raw reads per point: %.1f ns per point = "
      "%.2f M points/s per core, %.2f M points/s on %d threads\n",
      symbols, raws, floor_ns, 1e3 / floor_ns, threads * 1e3 / floor_ns, threads);
  std::printf(
      "the same counts through splatkit's decoder calls alone: %.1f ns per point = "
      "%.2f M points/s on %d threads\n",
      ours_floor_ns, threads * 1e3 / ours_floor_ns, threads);
  return 0;
}
