#include "colmap_ext/shard/shard_file.h"

#include <Eigen/Core>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "colmap_ext/database/sqlite_util.h"

namespace madsfm::colmap {
namespace {

using sqlite::Exec;
using sqlite::Statement;

constexpr const char* kFormat = "madsfm-shard-1";

// Little-endian blob writer / reader (x86 and ARM clusters are little-endian; the format names its version).
class BlobWriter {
 public:
  template <typename T>
  void Put(const T& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void PutDoubles(const double* v, int n) {
    for (int i = 0; i < n; ++i) Put(v[i]);
  }
  const std::vector<unsigned char>& bytes() const { return bytes_; }

 private:
  std::vector<unsigned char> bytes_;
};

class BlobReader {
 public:
  BlobReader(const void* data, size_t size, std::string what)
      : p_(static_cast<const unsigned char*>(data)), size_(size), what_(std::move(what)) {}
  template <typename T>
  T Get() {
    if (pos_ + sizeof(T) > size_) throw std::runtime_error(what_ + ": blob too short");
    T v;
    std::memcpy(&v, p_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  void GetDoubles(double* v, int n) {
    for (int i = 0; i < n; ++i) v[i] = Get<double>();
  }
  size_t remaining() const { return size_ - pos_; }
  [[noreturn]] void Fail(const std::string& message) const { throw std::runtime_error(what_ + ": " + message); }
  void ExpectEnd() const {
    if (pos_ != size_) throw std::runtime_error(what_ + ": blob has " + std::to_string(size_ - pos_) + " extra bytes");
  }

 private:
  const unsigned char* p_;
  size_t size_, pos_ = 0;
  std::string what_;
};

std::vector<unsigned char> EncodeGeometry(const TwoViewGeometryRow& g) {
  BlobWriter w;
  const uint8_t flags = (g.F ? 1 : 0) | (g.E ? 2 : 0) | (g.H ? 4 : 0) | (g.qvec ? 8 : 0) | (g.tvec ? 16 : 0) |
                        (g.camera1 ? 32 : 0) | (g.camera2 ? 64 : 0);
  w.Put(flags);
  w.Put(static_cast<int32_t>(g.config));
  w.Put(static_cast<uint64_t>(g.inlier_matches.size()));
  for (const auto& m : g.inlier_matches) {
    w.Put(m[0]);
    w.Put(m[1]);
  }
  for (const auto* M : {&g.F, &g.E, &g.H}) {
    if (*M) w.PutDoubles((*M)->data(), 9);  // column-major Eigen storage, read back the same way
  }
  if (g.qvec) w.PutDoubles(g.qvec->data(), 4);
  if (g.tvec) w.PutDoubles(g.tvec->data(), 3);
  for (const auto* camera : {&g.camera1, &g.camera2}) {
    if (!*camera) continue;
    const std::vector<unsigned char> blob = EncodeCameraBlob(**camera);  // COLMAP's camera blob, length first
    w.Put(static_cast<uint32_t>(blob.size()));
    for (unsigned char b : blob) w.Put(b);
  }
  return w.bytes();
}

TwoViewGeometryRow DecodeGeometry(pair_t pair_id, BlobReader r) {
  TwoViewGeometryRow g;
  g.pair_id = pair_id;
  const auto flags = r.Get<uint8_t>();
  g.config = r.Get<int32_t>();
  const auto n = r.Get<uint64_t>();
  // Checked against the bytes left before allocating: a corrupt count must not become a huge allocation.
  if (n > r.remaining() / (2 * sizeof(uint32_t))) {
    r.Fail("blob too short for its " + std::to_string(n) + " inlier matches");
  }
  g.inlier_matches.resize(n);
  for (auto& m : g.inlier_matches) {
    m[0] = r.Get<uint32_t>();
    m[1] = r.Get<uint32_t>();
  }
  std::optional<Eigen::Matrix3d>* mats[3] = {&g.F, &g.E, &g.H};
  for (int k = 0; k < 3; ++k) {
    if (flags & (1 << k)) {
      Eigen::Matrix3d M;
      r.GetDoubles(M.data(), 9);
      *mats[k] = M;
    }
  }
  if (flags & 8) {
    Eigen::Vector4d q;
    r.GetDoubles(q.data(), 4);
    g.qvec = q;
  }
  if (flags & 16) {
    Eigen::Vector3d t;
    r.GetDoubles(t.data(), 3);
    g.tvec = t;
  }
  std::optional<Camera>* cameras[2] = {&g.camera1, &g.camera2};
  for (int k = 0; k < 2; ++k) {
    if (!(flags & (32 << k))) continue;
    const auto num_bytes = r.Get<uint32_t>();
    if (num_bytes > r.remaining()) r.Fail("blob too short for its camera" + std::to_string(k + 1));
    std::vector<unsigned char> blob(num_bytes);
    for (auto& b : blob) b = r.Get<unsigned char>();
    *cameras[k] = DecodeCameraBlob(blob.data(), blob.size(), "camera" + std::to_string(k + 1) + " of the geometry");
  }
  r.ExpectEnd();
  return g;
}

std::vector<unsigned char> EncodeMadsfm(const MadsfmPairRow& m) {
  BlobWriter w;
  w.PutDoubles(m.R.data(), 9);
  w.PutDoubles(m.t.data(), 3);
  const double reals[6] = {m.scale, m.shift1, m.shift2, m.focal1, m.focal2, m.score};
  w.PutDoubles(reals, 6);
  for (int v : {m.camera_mode, m.method, m.num_inliers_reproj1, m.num_inliers_reproj2, m.num_inliers_sampson,
                m.num_inliers, m.status}) {
    w.Put(static_cast<int32_t>(v));
  }
  // Since the depth observability was stored: int32 depth_observable, 3 doubles (older shards end before).
  w.Put(static_cast<int32_t>(m.depth_observable));
  const double sigmas[3] = {m.sigma_scale, m.sigma_shift1, m.sigma_shift2};
  w.PutDoubles(sigmas, 3);
  // Since the focal standard deviations were stored: 2 doubles (older shards end before).
  const double focal_sigmas[2] = {m.sigma_focal1, m.sigma_focal2};
  w.PutDoubles(focal_sigmas, 2);
  return w.bytes();
}

MadsfmPairRow DecodeMadsfm(pair_t pair_id, const std::string& options_fingerprint, BlobReader r) {
  MadsfmPairRow m;
  m.pair_id = pair_id;
  m.options_fingerprint = options_fingerprint;
  r.GetDoubles(m.R.data(), 9);
  r.GetDoubles(m.t.data(), 3);
  double reals[6];
  r.GetDoubles(reals, 6);
  m.scale = reals[0];
  m.shift1 = reals[1];
  m.shift2 = reals[2];
  m.focal1 = reals[3];
  m.focal2 = reals[4];
  m.score = reals[5];
  for (int* v : {&m.camera_mode, &m.method, &m.num_inliers_reproj1, &m.num_inliers_reproj2, &m.num_inliers_sampson,
                 &m.num_inliers, &m.status}) {
    *v = r.Get<int32_t>();
  }
  if (r.remaining() > 0) {  // shards written before the depth observability end here
    m.depth_observable = r.Get<int32_t>();
    if (m.depth_observable < -1 || m.depth_observable > 1) r.Fail("depth_observable must be -1, 0 or 1");
    double sigmas[3];
    r.GetDoubles(sigmas, 3);
    m.sigma_scale = sigmas[0];
    m.sigma_shift1 = sigmas[1];
    m.sigma_shift2 = sigmas[2];
  }
  if (r.remaining() > 0) {  // shards written before the focal standard deviations end here
    double focal_sigmas[2];
    r.GetDoubles(focal_sigmas, 2);
    m.sigma_focal1 = focal_sigmas[0];
    m.sigma_focal2 = focal_sigmas[1];
  }
  r.ExpectEnd();
  return m;
}

std::map<std::string, std::string> InfoToMap(const ShardInfo& i) {
  return {{"format", kFormat},
          {"database_path", i.database_path},
          {"database_fingerprint", i.database_fingerprint},
          {"options_fingerprint", i.options_fingerprint},
          {"split_fingerprint", i.split_fingerprint},
          {"num_shards", std::to_string(i.num_shards)},
          {"shard_index", std::to_string(i.shard_index)},
          {"num_split_pairs", std::to_string(i.num_split_pairs)},
          {"min_num_matches", std::to_string(i.min_num_matches)},
          {"pair_list_path", i.pair_list_path},
          {"pair_list_fingerprint", i.pair_list_fingerprint},
          {"madsfm_version", i.madsfm_version}};
}

ShardInfo InfoFromMap(const std::map<std::string, std::string>& m, const std::string& path) {
  auto get = [&](const std::string& key) -> const std::string& {
    const auto it = m.find(key);
    if (it == m.end()) throw std::runtime_error("shard file '" + path + "' lacks the info key '" + key + "'");
    return it->second;
  };
  auto get_int = [&](const std::string& key) -> long long {
    const std::string& v = get(key);
    try {
      size_t used = 0;
      const long long x = std::stoll(v, &used);
      if (used == v.size()) return x;
    } catch (const std::exception&) {
    }
    throw std::runtime_error("shard file '" + path + "': info '" + key + "' is not an integer ('" + v + "')");
  };
  if (get("format") != kFormat) {
    throw std::runtime_error("shard file '" + path + "' has format '" + get("format") + "', this madsfm reads '" +
                             kFormat + "'");
  }
  ShardInfo i;
  i.database_path = get("database_path");
  i.database_fingerprint = get("database_fingerprint");
  i.options_fingerprint = get("options_fingerprint");
  i.split_fingerprint = get("split_fingerprint");
  i.num_shards = static_cast<int>(get_int("num_shards"));
  i.shard_index = static_cast<int>(get_int("shard_index"));
  i.num_split_pairs = get_int("num_split_pairs");
  i.min_num_matches = static_cast<int>(get_int("min_num_matches"));
  i.pair_list_path = get("pair_list_path");
  i.pair_list_fingerprint = get("pair_list_fingerprint");
  i.madsfm_version = get("madsfm_version");
  if (i.num_shards < 1 || i.shard_index < 0 || i.shard_index >= i.num_shards) {
    throw std::runtime_error("shard file '" + path + "': shard_index " + std::to_string(i.shard_index) +
                             " is not in [0, num_shards = " + std::to_string(i.num_shards) + ")");
  }
  return i;
}

sqlite3* OpenSqlite(const std::string& path, int flags) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, flags, nullptr) != SQLITE_OK) {
    const std::string msg = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw std::runtime_error("cannot open shard file '" + path + "': " + msg);
  }
  sqlite3_busy_timeout(db, 5000);
  return db;
}

std::vector<pair_t> ReadPairColumn(sqlite3* db, const std::string& path, const char* sql) {
  Statement st(db, path, sql);
  std::vector<pair_t> pairs;
  while (st.Step()) pairs.push_back(static_cast<pair_t>(st.Int64(0)));
  return pairs;
}

}  // namespace

std::unique_ptr<ShardFile> ShardFile::Create(const std::string& path, const ShardInfo& info,
                                             const std::vector<pair_t>& assigned_pairs) {
  namespace fs = std::filesystem;
  if (fs::exists(path)) throw std::runtime_error("shard file '" + path + "' already exists");
  const std::string tmp = path + ".tmp";
  std::error_code ec;
  fs::remove(tmp, ec);  // left over from a task killed while creating it
  {
    sqlite3* db = OpenSqlite(tmp, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    try {
      Exec(db, tmp,
           "BEGIN;"
           "CREATE TABLE madsfm_shard_info (key TEXT PRIMARY KEY NOT NULL, value TEXT NOT NULL);"
           "CREATE TABLE madsfm_shard_pairs (pair_id INTEGER PRIMARY KEY NOT NULL);"
           "CREATE TABLE madsfm_shard_results (pair_id INTEGER PRIMARY KEY NOT NULL, geometry BLOB, "
           "madsfm BLOB NOT NULL);");
      {
        Statement st(db, tmp, "INSERT INTO madsfm_shard_info(key, value) VALUES(?, ?)");
        for (const auto& [key, value] : InfoToMap(info)) {
          st.BindText(1, key);
          st.BindText(2, value);
          st.Run();
          st.Reset();
        }
        Statement pairs(db, tmp, "INSERT INTO madsfm_shard_pairs(pair_id) VALUES(?)");
        for (pair_t p : assigned_pairs) {
          pairs.BindInt64(1, static_cast<int64_t>(p));
          pairs.Run();
          pairs.Reset();
        }
      }
      Exec(db, tmp, "COMMIT");
    } catch (...) {
      sqlite3_close(db);
      fs::remove(tmp, ec);
      throw;
    }
    sqlite3_close(db);
  }
  fs::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("cannot rename '" + tmp + "' to '" + path + "': " + ec.message());
  return Open(path, /*read_only=*/false);
}

std::unique_ptr<ShardFile> ShardFile::Open(const std::string& path, bool read_only) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error("shard file '" + path + "' does not exist");
  std::unique_ptr<ShardFile> shard(new ShardFile());
  shard->path_ = path;
  if (read_only) sqlite::RollBackHotJournal(path, 5000);  // a task killed mid-batch: merge what it committed
  shard->db_ = OpenSqlite(path, read_only ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE);
  std::map<std::string, std::string> info;
  try {
    Statement st(shard->db_, path, "SELECT key, value FROM madsfm_shard_info");
    while (st.Step()) info[st.Text(0)] = st.Text(1);
  } catch (const std::exception& e) {
    throw std::runtime_error("'" + path + "' is not a madsfm shard file (" + e.what() + ")");
  }
  shard->info_ = InfoFromMap(info, path);
  return shard;
}

ShardFile::~ShardFile() {
  if (in_transaction_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
  sqlite3_close(db_);
}

std::vector<pair_t> ShardFile::AssignedPairs() const {
  return ReadPairColumn(db_, path_, "SELECT pair_id FROM madsfm_shard_pairs ORDER BY pair_id");
}

std::vector<pair_t> ShardFile::ResultPairs() const {
  return ReadPairColumn(db_, path_, "SELECT pair_id FROM madsfm_shard_results ORDER BY pair_id");
}

void ShardFile::Begin() {
  Exec(db_, path_, "BEGIN IMMEDIATE");
  in_transaction_ = true;
}

void ShardFile::Commit() {
  Exec(db_, path_, "COMMIT");
  in_transaction_ = false;
}

void ShardFile::WriteResult(const ShardResult& result) {
  if (!in_transaction_) throw std::logic_error("ShardFile::WriteResult outside Begin()/Commit()");
  Statement st(db_, path_, "INSERT OR REPLACE INTO madsfm_shard_results(pair_id, geometry, madsfm) VALUES(?, ?, ?)");
  st.BindInt64(1, static_cast<int64_t>(result.madsfm.pair_id));
  if (result.geometry) {
    const auto g = EncodeGeometry(*result.geometry);
    st.BindBlob(2, g.data(), g.size());
  } else {
    st.BindNull(2);
  }
  const auto m = EncodeMadsfm(result.madsfm);
  st.BindBlob(3, m.data(), m.size());
  st.Run();
}

void ShardFile::ForEachResult(const std::function<void(const ShardResult&)>& visit) const {
  Statement st(db_, path_, "SELECT pair_id, geometry, madsfm FROM madsfm_shard_results ORDER BY pair_id");
  while (st.Step()) {
    const auto pair_id = static_cast<pair_t>(st.Int64(0));
    const std::string what = "shard file '" + path_ + "', pair " + std::to_string(pair_id);
    ShardResult result;
    size_t n = 0;
    if (!st.IsNull(1)) {
      const void* data = st.Blob(1, &n);
      result.geometry = DecodeGeometry(pair_id, BlobReader(data, n, what + " geometry"));
    }
    const void* data = st.Blob(2, &n);
    result.madsfm = DecodeMadsfm(pair_id, info_.options_fingerprint, BlobReader(data, n, what + " result"));
    visit(result);
  }
}

}  // namespace madsfm::colmap
