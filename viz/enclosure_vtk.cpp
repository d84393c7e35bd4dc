// Enclosure <-> .vtu (enclosure_vtk.h). The arrays are filled through raw pointers in parallel so
// that a million voxels convert in a fraction of a second; the rest is VTK's writer, with LZ4
// compression, the fastest it offers (docs/enclose.md, "Speed").
#include "viz/enclosure_vtk.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>
#include <numeric>

#include <vtkCallbackCommand.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkPoints.h>
#include <vtkSignedCharArray.h>
#include <vtkStringArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkTypeUInt32Array.h>
#include <vtkTypeUInt64Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkVariant.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "core/error.h"

namespace iaa::viz {

namespace {

constexpr const char* kFormat = "iaa-enclosure 1";

template <class A>
vtkSmartPointer<A> make_array(const char* name, int components, vtkIdType tuples) {
  auto a = vtkSmartPointer<A>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

template <class A, class T>
vtkSmartPointer<A> scalar_field(const char* name, T value) {
  auto a = make_array<A>(name, 1, 1);
  a->SetValue(0, value);
  return a;
}

/// Cells per chunk of the point numbering.
constexpr std::size_t kChunk = 1024;

/// The unique corners of one chunk and its connectivity in chunk-local point numbers.
struct ChunkPoints {
  std::vector<std::array<std::uint32_t, 3>> keys;
  std::vector<std::uint32_t> local;
};

/// Open-addressing map from a corner to its chunk-local number; sized for a whole chunk's 8
/// corners per cell at half load, so it never grows; cleared between chunks.
class CornerTable {
 public:
  CornerTable() : slots_(kSize) {}
  /// Empties the table in time proportional to what it holds.
  void clear() {
    for (std::size_t i : used_) slots_[i] = Slot{};
    used_.clear();
  }
  std::uint32_t id(const std::array<std::uint32_t, 3>& k,
                   std::vector<std::array<std::uint32_t, 3>>* keys) {
    std::uint64_t h =
        k[0] * 0x9E3779B97F4A7C15ull ^ k[1] * 0xC2B2AE3D27D4EB4Full ^ k[2] * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    for (std::size_t i = h & (kSize - 1);; i = (i + 1) & (kSize - 1)) {
      Slot& s = slots_[i];
      if (s.id == kEmpty) {
        s = Slot{k, static_cast<std::uint32_t>(keys->size())};
        keys->push_back(k);
        used_.push_back(i);
        return s.id;
      }
      if (s.key[0] == k[0] && s.key[1] == k[1] && s.key[2] == k[2]) return s.id;
    }
  }

 private:
  static constexpr std::size_t kSize = 16 * kChunk;
  static constexpr std::uint32_t kEmpty = 0xffffffffu;
  struct Slot {
    std::array<std::uint32_t, 3> key{};
    std::uint32_t id = kEmpty;
  };
  std::vector<Slot> slots_;
  std::vector<std::size_t> used_;
};

vtkDataArray* cell_array(vtkUnstructuredGrid* g, const char* name, int components, vtkIdType tuples,
                         const std::string& path) {
  vtkDataArray* a = g->GetCellData()->GetArray(name);
  if (!a || a->GetNumberOfComponents() != components || a->GetNumberOfTuples() != tuples) {
    throw Error("'" + path + "' is not an iaa enclosure: cell array '" + name +
                "' is missing or has the wrong shape");
  }
  return a;
}

vtkAbstractArray* field(vtkUnstructuredGrid* g, const char* name, const std::string& path) {
  vtkAbstractArray* a = g->GetFieldData()->GetAbstractArray(name);
  if (!a || a->GetNumberOfValues() < 1) {
    throw Error("'" + path + "' is not an iaa enclosure: field data '" + name + "' is missing");
  }
  return a;
}

std::uint64_t field_number(vtkUnstructuredGrid* g, const char* name, const std::string& path) {
  auto* a = vtkDataArray::SafeDownCast(field(g, name, path));
  if (!a) throw Error("'" + path + "': field data '" + name + "' is not numeric");
  bool ok = false;
  const vtkTypeUInt64 v = a->GetVariantValue(0).ToTypeUInt64(&ok);
  if (!ok) throw Error("'" + path + "': field data '" + name + "' is not a count");
  return v;
}

/// The deepest depth that holds a cell: the grid on which corners are numbered. Taken from the
/// cells themselves (not counts_by_depth), so that any set of cells converts, such as the boxes a
/// mesher left unmeshed.
int deepest_depth(const Enclosure& enc) {
  int max_depth = 0;
  for (const Cell& c : enc.cells) max_depth = std::max(max_depth, static_cast<int>(c.depth));
  return max_depth;
}

/// Pass 1, per chunk of consecutive cells (compact in space: Morton order): the chunk's unique
/// corners, as integer positions on the grid of the deepest cells, and its connectivity in
/// chunk-local point numbers. Corners shared across chunks are repeated, which costs little.
std::vector<ChunkPoints> number_corners(const Enclosure& enc, int max_depth) {
  const std::size_t n = enc.cells.size();
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<ChunkPoints> parts(chunks);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const auto& r) {
    CornerTable table;
    for (std::size_t ch = r.begin(); ch != r.end(); ++ch) {
      table.clear();
      ChunkPoints& part = parts[ch];
      const std::size_t b = ch * kChunk, e = std::min(n, b + kChunk);
      part.local.resize(8 * (e - b));
      for (std::size_t i = b; i < e; ++i) {
        const Cell& c = enc.cells[i];
        const int shift = max_depth - c.depth;
        // VTK_VOXEL order: x fastest, then y, then z (the octree's child order).
        for (int k = 0; k < 8; ++k) {
          const std::array<std::uint32_t, 3> key{(c.index[0] + (k & 1)) << shift,
                                                 (c.index[1] + ((k >> 1) & 1)) << shift,
                                                 (c.index[2] + ((k >> 2) & 1)) << shift};
          part.local[8 * (i - b) + k] = table.id(key, &part.keys);
        }
      }
    }
  });
  return parts;
}

/// The arrays of the grid, allocated at their final size and filled through raw pointers.
struct VoxelArrays {
  VoxelArrays(vtkIdType nc, vtkIdType np)
      // 32-bit connectivity and offsets when they fit: VTK 9 writes a cell array's own storage
      // type, so this halves their bytes in the file (and the time to compress them).
      : narrow(8 * nc < (vtkIdType{1} << 31) && np < (vtkIdType{1} << 31)),
        coords(make_array<vtkDoubleArray>("Points", 3, np)),
        conn32(make_array<vtkTypeInt32Array>("connectivity", 1, narrow ? 8 * nc : 0)),
        offsets32(make_array<vtkTypeInt32Array>("offsets", 1, narrow ? nc + 1 : 0)),
        conn64(make_array<vtkTypeInt64Array>("connectivity", 1, narrow ? 0 : 8 * nc)),
        offsets64(make_array<vtkTypeInt64Array>("offsets", 1, narrow ? 0 : nc + 1)),
        types(make_array<vtkUnsignedCharArray>("types", 1, nc)),
        depth(make_array<vtkUnsignedCharArray>("depth", 1, nc)),
        cls(make_array<vtkSignedCharArray>("class", 1, nc)),
        flo(make_array<vtkDoubleArray>("f_lo", 1, nc)),
        fhi(make_array<vtkDoubleArray>("f_hi", 1, nc)),
        index(make_array<vtkTypeUInt32Array>("index", 3, nc)),
        cn32(conn32->GetPointer(0)),
        of32(offsets32->GetPointer(0)),
        cn64(conn64->GetPointer(0)),
        of64(offsets64->GetPointer(0)) {}

  /// Sets entry i of the connectivity (or offsets) in whichever width is in use.
  void set_id(vtkTypeInt32* a32, vtkTypeInt64* a64, std::size_t i, std::uint64_t v) const {
    if (narrow) {
      a32[i] = static_cast<vtkTypeInt32>(v);
    } else {
      a64[i] = static_cast<vtkTypeInt64>(v);
    }
  }

  bool narrow;
  vtkSmartPointer<vtkDoubleArray> coords;
  vtkSmartPointer<vtkTypeInt32Array> conn32, offsets32;
  vtkSmartPointer<vtkTypeInt64Array> conn64, offsets64;
  vtkSmartPointer<vtkUnsignedCharArray> types, depth;
  // Int8, not UInt8: VTK mappers draw unsigned char scalars as colours instead of mapping them.
  vtkSmartPointer<vtkSignedCharArray> cls;
  vtkSmartPointer<vtkDoubleArray> flo, fhi;
  vtkSmartPointer<vtkTypeUInt32Array> index;
  // Raw storage of the connectivity and offsets, taken once: GetPointer is not for threads.
  vtkTypeInt32 *cn32, *of32;
  vtkTypeInt64 *cn64, *of64;
};

/// Pass 2: global point numbers (chunk `ch` starts at base[ch]) and the arrays. Grid coordinates
/// are defined with upward rounding (octree.h), which makes the points exactly the corners of
/// Enclosure::box. Each chunk's pass-1 data is freed as soon as it is used.
void fill_arrays(const Enclosure& enc, int max_depth, std::vector<ChunkPoints>& parts,
                 const std::vector<std::uint64_t>& base, VoxelArrays& v) {
  const std::size_t n = enc.cells.size();
  double* p = v.coords->GetPointer(0);
  unsigned char* ty = v.types->GetPointer(0);
  unsigned char* de = v.depth->GetPointer(0);
  signed char* cl = v.cls->GetPointer(0);
  double* lo = v.flo->GetPointer(0);
  double* hi = v.fhi->GetPointer(0);
  std::uint32_t* ix = v.index->GetPointer(0);
  v.set_id(v.of32, v.of64, n, 8 * n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, parts.size(), 1), [&](const auto& r) {
    RoundingScope scope;
    for (std::size_t ch = r.begin(); ch != r.end(); ++ch) {
      ChunkPoints& part = parts[ch];
      const std::uint64_t pb = base[ch];
      for (std::size_t j = 0; j < part.keys.size(); ++j) {
        for (int a = 0; a < 3; ++a) {
          p[3 * (pb + j) + a] = grid_coordinate_upward(enc.bounds.lo[a], enc.bounds.hi[a],
                                                       part.keys[j][a], max_depth);
        }
      }
      const std::size_t b = ch * kChunk, e = std::min(n, b + kChunk);
      for (std::size_t i = b; i < e; ++i) {
        const Cell& c = enc.cells[i];
        for (int k = 0; k < 8; ++k) {
          v.set_id(v.cn32, v.cn64, 8 * i + k, pb + part.local[8 * (i - b) + k]);
        }
        v.set_id(v.of32, v.of64, i, 8 * i);
        ty[i] = VTK_VOXEL;
        de[i] = c.depth;
        cl[i] = static_cast<signed char>(c.cls);
        // A zero bound is written as +0: VTK computes each array's range (written in the
        // header) over threads, and of a -0 and a +0 the one it keeps depends on their order,
        // so a file with both would differ from run to run in its RangeMin/RangeMax.
        lo[i] = c.f.lo() == 0.0 ? 0.0 : c.f.lo();
        hi[i] = c.f.hi() == 0.0 ? 0.0 : c.f.hi();
        for (int a = 0; a < 3; ++a) ix[3 * i + a] = c.index[a];
      }
      ChunkPoints().keys.swap(part.keys);
      std::vector<std::uint32_t>().swap(part.local);
    }
  });
}

/// The grid of the filled arrays, with `class` as the active scalars.
vtkSmartPointer<vtkUnstructuredGrid> make_grid(const VoxelArrays& v) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(v.coords);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  if (v.narrow) {
    cells->SetData(v.offsets32, v.conn32);
  } else {
    cells->SetData(v.offsets64, v.conn64);
  }
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(v.types, cells);
  vtkCellData* cd = grid->GetCellData();
  cd->AddArray(v.depth);
  cd->AddArray(v.cls);
  cd->AddArray(v.flo);
  cd->AddArray(v.fhi);
  cd->AddArray(v.index);
  cd->SetActiveScalars("class");
  return grid;
}

/// The field data of the file layout (enclosure_vtk.h): format, expression, bounds, settings
/// and evaluation counts.
void add_fields(vtkUnstructuredGrid* grid, const Enclosure& enc, const EnclosureInfo& info) {
  vtkFieldData* fd = grid->GetFieldData();
  auto format = make_array<vtkStringArray>("format", 1, 1);
  format->SetValue(0, kFormat);
  fd->AddArray(format);
  auto expr = make_array<vtkStringArray>("expression", 1, 1);
  expr->SetValue(0, info.expression);
  fd->AddArray(expr);
  auto bounds = make_array<vtkDoubleArray>("bounds", 1, 6);
  for (int a = 0; a < 3; ++a) {
    bounds->SetValue(2 * a, enc.bounds.lo[a]);
    bounds->SetValue(2 * a + 1, enc.bounds.hi[a]);
  }
  fd->AddArray(bounds);
  fd->AddArray(scalar_field<vtkUnsignedCharArray>("depth", info.settings.depth));
  fd->AddArray(
      scalar_field<vtkUnsignedCharArray>("refine_possible", info.settings.refine_possible));
  fd->AddArray(scalar_field<vtkTypeUInt64Array>("max_boxes", info.settings.max_boxes));
  fd->AddArray(scalar_field<vtkTypeUInt64Array>("evaluations", enc.evaluations));
  fd->AddArray(scalar_field<vtkTypeUInt64Array>("corner_evaluations", enc.corner_evaluations));
}

}  // namespace

vtkSmartPointer<vtkUnstructuredGrid> enclosure_to_grid(const Enclosure& enc,
                                                       const EnclosureInfo& info) {
  const int max_depth = deepest_depth(enc);
  std::vector<ChunkPoints> parts = number_corners(enc, max_depth);
  // Each chunk's points follow those of the chunks before it.
  std::vector<std::uint64_t> base(parts.size() + 1, 0);
  for (std::size_t ch = 0; ch < parts.size(); ++ch) base[ch + 1] = base[ch] + parts[ch].keys.size();
  VoxelArrays arrays(static_cast<vtkIdType>(enc.cells.size()), static_cast<vtkIdType>(base.back()));
  fill_arrays(enc, max_depth, parts, base, arrays);
  vtkSmartPointer<vtkUnstructuredGrid> grid = make_grid(arrays);
  add_fields(grid, enc, info);
  return grid;
}

void write_enclosure_vtu(const std::string& path, const Enclosure& enc, const EnclosureInfo& info,
                         Progress* progress) {
  write_grid_vtu(path, enclosure_to_grid(enc, info), progress);
}

void write_grid_vtu(const std::string& path, vtkUnstructuredGrid* grid, Progress* progress) {
  auto writer = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
  writer->SetFileName(path.c_str());
  writer->SetInputData(grid);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();  // raw binary, not base64
  writer->SetCompressorTypeToLZ4();
  writer->SetCompressionLevel(1);  // LZ4's fastest level (docs/enclose.md, "Speed")

  writer->SetHeaderTypeToUInt64();
  // Int32 point numbers when they fit: half the bytes of connectivity and offsets.
  if (grid->GetNumberOfCells() < (vtkIdType{1} << 27)) writer->SetIdTypeToInt32();
  writer->SetBlockSize(1 << 20);
  // Forward VTK's progress (0..1) to ours, in thousandths.
  ProgressPhase phase(progress, "write .vtu", 1000);
  struct Forward {
    ProgressPhase* phase;
    std::uint64_t done = 0;
  } forward{&phase};
  auto observer = vtkSmartPointer<vtkCallbackCommand>::New();
  observer->SetClientData(&forward);
  observer->SetCallback([](vtkObject* caller, unsigned long, void* client, void*) {
    auto* f = static_cast<Forward*>(client);
    const auto now =
        static_cast<std::uint64_t>(1000.0 * static_cast<vtkAlgorithm*>(caller)->GetProgress());
    if (now > f->done) {
      f->phase->advance(now - f->done);
      f->done = now;
    }
  });
  if (progress) writer->AddObserver(vtkCommand::ProgressEvent, observer);
  if (writer->Write() != 1 || writer->GetErrorCode() != 0) {
    throw Error("cannot write '" + path + "': the VTK writer failed");
  }
}

VtuWriteTimes write_enclosure_vtu_timed(const std::string& path, const Enclosure& enc,
                                        const EnclosureInfo& info, const Exec& exec) {
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
  };
  VtuWriteTimes t;
  vtkSmartPointer<vtkUnstructuredGrid> grid;
  const auto t0 = Clock::now();
  exec.run([&] { grid = enclosure_to_grid(enc, info); });
  t.convert_s = seconds(t0);
  const auto t1 = Clock::now();
  write_grid_vtu(path, grid);
  t.write_s = seconds(t1);
  return t;
}

namespace {

/// The field data: format, expression, bounds, settings (validated) and evaluation counts.
void read_fields(vtkUnstructuredGrid* g, const std::string& path, EnclosureFile* out) {
  auto* format = vtkStringArray::SafeDownCast(field(g, "format", path));
  if (!format || format->GetValue(0) != kFormat) {
    throw Error("'" + path + "' is not an iaa enclosure (no format '" + kFormat + "')");
  }
  auto* expr = vtkStringArray::SafeDownCast(field(g, "expression", path));
  if (!expr) throw Error("'" + path + "': field data 'expression' is not a string");
  out->info.expression = expr->GetValue(0);
  auto* bounds = vtkDataArray::SafeDownCast(field(g, "bounds", path));
  if (!bounds || bounds->GetNumberOfValues() != 6) {
    throw Error("'" + path + "': field data 'bounds' must hold 6 numbers");
  }
  Enclosure& enc = out->enclosure;
  for (int a = 0; a < 3; ++a) {
    enc.bounds.lo[a] = bounds->GetComponent(2 * a, 0);
    enc.bounds.hi[a] = bounds->GetComponent(2 * a + 1, 0);
  }
  EncloseSettings& s = out->info.settings;
  s.bounds = enc.bounds;
  s.depth = static_cast<int>(field_number(g, "depth", path));
  s.refine_possible = static_cast<int>(field_number(g, "refine_possible", path));
  s.max_boxes = field_number(g, "max_boxes", path);
  enc.evaluations = field_number(g, "evaluations", path);
  enc.corner_evaluations = field_number(g, "corner_evaluations", path);
  s.validate();
}

/// The cells from the cell arrays, each checked to have a depth up to `max_depth` and a class,
/// and the counts per depth.
void read_cells(vtkUnstructuredGrid* g, const std::string& path, int max_depth, Enclosure* enc) {
  const vtkIdType nc = g->GetNumberOfCells();
  auto* depth = vtkUnsignedCharArray::SafeDownCast(cell_array(g, "depth", 1, nc, path));
  auto* cls = vtkSignedCharArray::SafeDownCast(cell_array(g, "class", 1, nc, path));
  auto* flo = vtkDoubleArray::SafeDownCast(cell_array(g, "f_lo", 1, nc, path));
  auto* fhi = vtkDoubleArray::SafeDownCast(cell_array(g, "f_hi", 1, nc, path));
  // The reader makes the platform's array classes (vtkUnsignedIntArray for UInt32).
  auto* index =
      vtkAOSDataArrayTemplate<vtkTypeUInt32>::SafeDownCast(cell_array(g, "index", 3, nc, path));
  if (!depth || !cls || !flo || !fhi || !index) {
    throw Error("'" + path + "' is not an iaa enclosure: a cell array has the wrong type");
  }
  enc->counts_by_depth.assign(static_cast<std::size_t>(max_depth + 1), {0, 0});
  enc->cells.resize(static_cast<std::size_t>(nc));
  for (vtkIdType i = 0; i < nc; ++i) {
    Cell& c = enc->cells[static_cast<std::size_t>(i)];
    c.depth = depth->GetValue(i);
    const signed char k = cls->GetValue(i);
    if (c.depth < 1 || c.depth > max_depth || (k != 1 && k != 2)) {
      throw Error("'" + path + "': cell " + std::to_string(i) + " has an invalid depth or class");
    }
    c.cls = static_cast<CellClass>(k);
    c.f = Interval(flo->GetValue(i), fhi->GetValue(i));
    for (int a = 0; a < 3; ++a) c.index[a] = index->GetValue(3 * i + a);
    ++enc->counts_by_depth[c.depth][k == 1 ? 0 : 1];
  }
}

/// True when every cell is a voxel whose 8 points are the corners of the box its index describes
/// (Enclosure::box), bit for bit.
bool points_match_boxes(vtkUnstructuredGrid* g, const Enclosure& enc) {
  vtkCellArray* cells = g->GetCells();
  vtkPoints* pts = g->GetPoints();
  RoundingScope scope;
  auto ids = vtkSmartPointer<vtkIdList>::New();
  for (vtkIdType i = 0; i < g->GetNumberOfCells(); ++i) {
    if (g->GetCellType(i) != VTK_VOXEL) return false;
    cells->GetCellAtId(i, ids);
    const Box3 box = enc.box(enc.cells[static_cast<std::size_t>(i)]);
    for (int k = 0; k < 8; ++k) {
      double q[3];
      pts->GetPoint(ids->GetId(k), q);
      if (q[0] != ((k & 1) ? box.hi.x : box.lo.x) || q[1] != ((k & 2) ? box.hi.y : box.lo.y) ||
          q[2] != ((k & 4) ? box.hi.z : box.lo.z)) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace

EnclosureFile read_enclosure_vtu(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw Error("cannot read '" + path + "': no such file");
  }
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* g = reader->GetOutput();
  if (reader->GetErrorCode() != 0 || !g) throw Error("cannot read '" + path + "' as a .vtu file");
  EnclosureFile out;
  read_fields(g, path, &out);
  const EncloseSettings& s = out.info.settings;
  read_cells(g, path, s.depth + s.refine_possible, &out.enclosure);
  out.points_match_boxes = points_match_boxes(g, out.enclosure);
  return out;
}

}  // namespace iaa::viz
