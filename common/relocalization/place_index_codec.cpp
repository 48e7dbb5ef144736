// The place index as a byte blob (PlaceIndex::Serialize / Deserialize). Layout, little-endian:
//   "FLPLACE\0" magic | u32 format version | options (i32 × 9, f64 blur) | string mosaic_id |
//   i64 mosaic version | f64 resolution | u64 count | count × (f64 x, f64 y, f64 heading) |
//   count × 32 descriptor bytes | u64 FNV-1a checksum of everything before it.
// Every read is bounds-checked, so a truncated or corrupt blob gives InvalidInput, never a crash;
// the LSH tables are rebuilt on load (a few hundred ms for a million features), not stored.
#include <cmath>
#include <cstring>
#include <string>

#include "relocalization/place_index.h"

namespace fleetloc::relocalization {
namespace {

constexpr char kMagic[8] = {'F', 'L', 'P', 'L', 'A', 'C', 'E', '\0'};
constexpr std::uint32_t kFormatVersion = 1;
constexpr int kDescriptorBytes = 32;
constexpr std::uint64_t kMaxFeatures = 1ULL << 28;

std::uint64_t Fnv1a(std::span<const std::uint8_t> bytes) {
  std::uint64_t hash = 1469598103934665603ULL;
  for (std::uint8_t b : bytes) hash = (hash ^ b) * 1099511628211ULL;
  return hash;
}

class Writer {
 public:
  template <typename T>
  void Put(const T& value) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void PutBytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + n);
  }
  void PutString(const std::string& s) {
    Put(static_cast<std::uint32_t>(s.size()));
    PutBytes(s.data(), s.size());
  }
  std::vector<std::uint8_t> Take() { return std::move(bytes_); }
  std::span<const std::uint8_t> bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  template <typename T>
  bool Get(T* value) {
    return GetBytes(value, sizeof(T));
  }
  bool GetBytes(void* out, std::size_t n) {
    if (n > bytes_.size() - offset_) return false;
    std::memcpy(out, bytes_.data() + offset_, n);
    offset_ += n;
    return true;
  }
  bool GetString(std::string* s, std::size_t max_size) {
    std::uint32_t n = 0;
    if (!Get(&n) || n > max_size || n > bytes_.size() - offset_) return false;
    s->assign(reinterpret_cast<const char*>(bytes_.data() + offset_), n);
    offset_ += n;
    return true;
  }
  std::size_t remaining() const { return bytes_.size() - offset_; }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t offset_ = 0;
};

void PutOptions(Writer& w, const PlaceIndexOptions& o) {
  const FloorFeatureOptions& f = o.features;
  for (int v : {f.level, f.cell_px, f.features_per_cell, f.fast_threshold, f.patch_size_px,
                o.strip_rows_px, o.lsh_tables, o.lsh_key_bits, o.lsh_multiprobe_level})
    w.Put(static_cast<std::int32_t>(v));
  w.Put(f.blur_sigma_px);
}

bool GetOptions(Reader& r, PlaceIndexOptions* o) {
  FloorFeatureOptions& f = o->features;
  std::int32_t v[9];
  for (std::int32_t& x : v)
    if (!r.Get(&x)) return false;
  f.level = v[0], f.cell_px = v[1], f.features_per_cell = v[2], f.fast_threshold = v[3];
  f.patch_size_px = v[4], o->strip_rows_px = v[5], o->lsh_tables = v[6];
  o->lsh_key_bits = v[7], o->lsh_multiprobe_level = v[8];
  return r.Get(&f.blur_sigma_px);
}

Status Corrupt(const std::string& what) { return InvalidInput("place index blob: " + what); }

}  // namespace

// Friend of PlaceIndex: reads and writes its private fields.
class PlaceIndexCodec {
 public:
  static std::vector<std::uint8_t> Encode(const PlaceIndex& index) {
    Writer w;
    w.PutBytes(kMagic, sizeof(kMagic));
    w.Put(kFormatVersion);
    PutOptions(w, index.options_);
    w.PutString(index.mosaic_id_);
    w.Put(static_cast<std::int64_t>(index.mosaic_version_));
    w.Put(index.resolution_m_);
    w.Put(static_cast<std::uint64_t>(index.size()));
    for (std::size_t i = 0; i < index.size(); ++i) {
      w.Put(index.positions_m_[i].x()), w.Put(index.positions_m_[i].y());
      w.Put(index.headings_rad_[i]);
    }
    const cv::Mat descriptors = index.descriptors_.clone();  // continuous
    w.PutBytes(descriptors.data, descriptors.total());
    w.Put(Fnv1a(w.bytes()));
    return w.Take();
  }

  static Result<PlaceIndex> Decode(std::span<const std::uint8_t> blob) {
    if (blob.size() < sizeof(kMagic) + sizeof(std::uint64_t) ||
        std::memcmp(blob.data(), kMagic, sizeof(kMagic)) != 0) {
      return Corrupt("not a fleetloc place index (bad magic or too short: " +
                     std::to_string(blob.size()) + " bytes)");
    }
    const std::span<const std::uint8_t> body = blob.first(blob.size() - sizeof(std::uint64_t));
    std::uint64_t checksum = 0;
    std::memcpy(&checksum, blob.data() + body.size(), sizeof(checksum));
    Reader r(body);
    char magic[sizeof(kMagic)];
    std::uint32_t version = 0;
    r.GetBytes(magic, sizeof(magic));
    if (!r.Get(&version)) return Corrupt("truncated header");
    if (version != kFormatVersion) {
      return Corrupt("format version " + std::to_string(version) + " is not the supported " +
                     std::to_string(kFormatVersion));
    }
    if (Fnv1a(body) != checksum) return Corrupt("checksum mismatch (corrupt or truncated)");
    PlaceIndex index;
    std::int64_t mosaic_version = 0;
    std::uint64_t count = 0;
    if (!GetOptions(r, &index.options_) || !r.GetString(&index.mosaic_id_, 1024) ||
        !r.Get(&mosaic_version) || !r.Get(&index.resolution_m_) || !r.Get(&count)) {
      return Corrupt("truncated header");
    }
    FLEETLOC_RETURN_IF_ERROR(Validate(index.options_));
    if (!(std::isfinite(index.resolution_m_) && index.resolution_m_ > 0))
      return Corrupt("resolution is not a positive number");
    const std::uint64_t feature_bytes = 3 * sizeof(double) + kDescriptorBytes;
    if (count == 0 || count > kMaxFeatures || count * feature_bytes != r.remaining())
      return Corrupt("feature count " + std::to_string(count) + " does not match the blob size");
    index.mosaic_version_ = mosaic_version;
    FLEETLOC_RETURN_IF_ERROR(ReadFeatures(r, count, &index));
    FLEETLOC_RETURN_IF_ERROR(index.Finish());
    return index;
  }

 private:
  static Status ReadFeatures(Reader& r, std::uint64_t count, PlaceIndex* index) {
    index->positions_m_.resize(count);
    index->headings_rad_.resize(count);
    for (std::uint64_t i = 0; i < count; ++i) {
      double x = 0, y = 0, heading = 0;
      r.Get(&x), r.Get(&y), r.Get(&heading);
      if (!std::isfinite(x) || !std::isfinite(y) || !(std::abs(heading) <= M_PI + 1e-9))
        return Corrupt("feature " + std::to_string(i) + " has a non-finite position or heading");
      index->positions_m_[i] = {x, y};
      index->headings_rad_[i] = heading;
    }
    index->descriptors_.create(static_cast<int>(count), kDescriptorBytes, CV_8UC1);
    r.GetBytes(index->descriptors_.data, count * kDescriptorBytes);
    return Status::Ok();
  }
};

std::vector<std::uint8_t> PlaceIndex::Serialize() const { return PlaceIndexCodec::Encode(*this); }

Result<PlaceIndex> PlaceIndex::Deserialize(std::span<const std::uint8_t> blob) {
  return PlaceIndexCodec::Decode(blob);
}

}  // namespace fleetloc::relocalization
