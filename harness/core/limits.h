// Every size limit pxh applies to its input, in one place: what a run may ask for (samples,
// rows, memory, GL time), what a height-field image or a plug-in shader may be, and the byte
// units the command line takes them in. The checks themselves stay where the input is read
// (each names its FILE:LINE or option); the numbers live here.
#pragma once
#include <cstddef>
#include <string>

namespace pxh {

// Samples (and a perspective camera's resolution) per side: `samples`, `resolution`,
// pxh run --samples, pxh bench --samples.
constexpr int kMaxSamples = 8192;

// pxh run's defaults for --max-rows and --max-memory (the run's estimate is checked against
// them before any work), and the bytes a result row is counted at until results.csv is written.
constexpr size_t kDefaultMaxRows = 1000000;
constexpr size_t kDefaultMaxMemoryBytes = size_t(8) << 30;  // 8 GiB
constexpr size_t kBytesPerRow = 1024;
// Rows of a backend in a process of its own that the side lane draws ahead of the rows scored
// (harness/run/side_lane.h): their outputs are held meanwhile (the memory estimate counts them,
// and the one being drawn).
constexpr size_t kSideRowsAhead = 4;

// gl_time_limit_s, pxh run --gl-time-limit: the default and the largest accepted (one day).
constexpr double kDefaultGlTimeLimitS = 120;
constexpr double kMaxGlTimeLimitS = 86400;

// Largest accepted height field image (any source that reads a W x H field from a file applies
// the same limits). Refused from the header, before the pixels are read: more than
// kMaxImageSide texels per side or kMaxImageTexels in all; more than kMaxImageChannels
// channels; more than kMaxImageBytes for all channels uncompressed, as stored (a tile, in tiled
// files, must fit the same limits). The largest field is 256 MiB of floats.
constexpr long long kMaxImageSide = 16384;
constexpr long long kMaxImageTexels = 64ll * 1024 * 1024;
constexpr long long kMaxImageChannels = 64;
constexpr long long kMaxImageBytes = 1024ll * 1024 * 1024;

// A plug-in shader file's largest accepted size.
constexpr size_t kMaxPluginShaderBytes = size_t(1) << 20;  // 1 MiB

// "123", "512M", "8G", "1.5T", "16GiB" (binary units) -> bytes; InputError(where, ...) for
// anything else (not a positive size, or past 1e18 bytes).
size_t parse_bytes(const std::string& text, const std::string& where);

// "512.0 MiB", "12.5 GiB": sizes in messages.
std::string format_bytes(size_t bytes);

}  // namespace pxh
