// Enclosure <-> .vtu (enclosure_vtk.h). The arrays are filled through raw pointers in parallel so
// that a million voxels convert in a fraction of a second; the rest is VTK's writer, with LZ4
// compression (zlib was several times slower for the same files).
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

}  // namespace

vtkSmartPointer<vtkUnstructuredGrid> enclosure_to_grid(const Enclosure& enc,
                                                       const EnclosureInfo& info) {
  const std::size_t n = enc.cells.size();
  const auto nc = static_cast<vtkIdType>(n);

  int max_depth = 0;
  for (std::size_t d = 0; d < enc.counts_by_depth.size(); ++d) {
    if (enc.counts_by_depth[d][0] + enc.counts_by_depth[d][1] > 0) max_depth = static_cast<int>(d);
  }

  // Pass 1, per chunk of consecutive cells (compact in space: Morton order): the chunk's unique
  // corners, as integer positions on the grid of the deepest cells, and its connectivity in
  // chunk-local point numbers. Corners shared across chunks are repeated, which costs little.
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
  std::vector<std::uint64_t> base(chunks + 1, 0);
  for (std::size_t ch = 0; ch < chunks; ++ch) base[ch + 1] = base[ch] + parts[ch].keys.size();
  const auto np = static_cast<vtkIdType>(base[chunks]);

  auto coords = make_array<vtkDoubleArray>("Points", 3, np);
  // 32-bit connectivity and offsets when they fit: VTK 9 writes a cell array's own storage type,
  // so this halves their bytes in the file (and the time to compress them).
  const bool narrow = 8 * nc < (vtkIdType{1} << 31) && np < (vtkIdType{1} << 31);
  auto conn32 = make_array<vtkTypeInt32Array>("connectivity", 1, narrow ? 8 * nc : 0);
  auto offsets32 = make_array<vtkTypeInt32Array>("offsets", 1, narrow ? nc + 1 : 0);
  auto conn64 = make_array<vtkTypeInt64Array>("connectivity", 1, narrow ? 0 : 8 * nc);
  auto offsets64 = make_array<vtkTypeInt64Array>("offsets", 1, narrow ? 0 : nc + 1);
  auto types = make_array<vtkUnsignedCharArray>("types", 1, nc);
  auto depth = make_array<vtkUnsignedCharArray>("depth", 1, nc);
  // Int8, not UInt8: VTK mappers draw unsigned char scalars as colours instead of mapping them.
  auto cls = make_array<vtkSignedCharArray>("class", 1, nc);
  auto flo = make_array<vtkDoubleArray>("f_lo", 1, nc);
  auto fhi = make_array<vtkDoubleArray>("f_hi", 1, nc);
  auto index = make_array<vtkTypeUInt32Array>("index", 3, nc);

  double* p = coords->GetPointer(0);
  vtkTypeInt32* cn32 = conn32->GetPointer(0);
  vtkTypeInt32* of32 = offsets32->GetPointer(0);
  vtkTypeInt64* cn64 = conn64->GetPointer(0);
  vtkTypeInt64* of64 = offsets64->GetPointer(0);
  const auto set_id = [&](vtkTypeInt32* a32, vtkTypeInt64* a64, std::size_t i, std::uint64_t v) {
    if (narrow) {
      a32[i] = static_cast<vtkTypeInt32>(v);
    } else {
      a64[i] = static_cast<vtkTypeInt64>(v);
    }
  };
  unsigned char* ty = types->GetPointer(0);
  unsigned char* de = depth->GetPointer(0);
  signed char* cl = cls->GetPointer(0);
  double* lo = flo->GetPointer(0);
  double* hi = fhi->GetPointer(0);
  std::uint32_t* ix = index->GetPointer(0);
  set_id(of32, of64, n, 8 * n);
  // Pass 2: global numbers and the arrays. Grid coordinates are defined with upward rounding
  // (octree.h), which makes the points exactly the corners of Enclosure::box.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const auto& r) {
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
        for (int k = 0; k < 8; ++k) set_id(cn32, cn64, 8 * i + k, pb + part.local[8 * (i - b) + k]);
        set_id(of32, of64, i, 8 * i);
        ty[i] = VTK_VOXEL;
        de[i] = c.depth;
        cl[i] = static_cast<signed char>(c.cls);
        lo[i] = c.f.lo();
        hi[i] = c.f.hi();
        for (int a = 0; a < 3; ++a) ix[3 * i + a] = c.index[a];
      }
      ChunkPoints().keys.swap(part.keys);
      std::vector<std::uint32_t>().swap(part.local);
    }
  });

  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(coords);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  if (narrow) {
    cells->SetData(offsets32, conn32);
  } else {
    cells->SetData(offsets64, conn64);
  }

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(types, cells);
  vtkCellData* cd = grid->GetCellData();
  cd->AddArray(depth);
  cd->AddArray(cls);
  cd->AddArray(flo);
  cd->AddArray(fhi);
  cd->AddArray(index);
  cd->SetActiveScalars("class");

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
  writer->SetCompressionLevel(1);  // LZ4's fastest: ~1 % larger files

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

  auto* format = vtkStringArray::SafeDownCast(field(g, "format", path));
  if (!format || format->GetValue(0) != kFormat) {
    throw Error("'" + path + "' is not an iaa enclosure (no format '" + kFormat + "')");
  }
  EnclosureFile out;
  auto* expr = vtkStringArray::SafeDownCast(field(g, "expression", path));
  if (!expr) throw Error("'" + path + "': field data 'expression' is not a string");
  out.info.expression = expr->GetValue(0);
  auto* bounds = vtkDataArray::SafeDownCast(field(g, "bounds", path));
  if (!bounds || bounds->GetNumberOfValues() != 6) {
    throw Error("'" + path + "': field data 'bounds' must hold 6 numbers");
  }
  Enclosure& enc = out.enclosure;
  for (int a = 0; a < 3; ++a) {
    enc.bounds.lo[a] = bounds->GetComponent(2 * a, 0);
    enc.bounds.hi[a] = bounds->GetComponent(2 * a + 1, 0);
  }
  EncloseSettings& s = out.info.settings;
  s.bounds = enc.bounds;
  s.depth = static_cast<int>(field_number(g, "depth", path));
  s.refine_possible = static_cast<int>(field_number(g, "refine_possible", path));
  s.max_boxes = field_number(g, "max_boxes", path);
  enc.evaluations = field_number(g, "evaluations", path);
  enc.corner_evaluations = field_number(g, "corner_evaluations", path);
  s.validate();

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
  const int max_depth = s.depth + s.refine_possible;
  enc.counts_by_depth.assign(static_cast<std::size_t>(max_depth + 1), {0, 0});
  enc.cells.resize(static_cast<std::size_t>(nc));
  for (vtkIdType i = 0; i < nc; ++i) {
    Cell& c = enc.cells[static_cast<std::size_t>(i)];
    c.depth = depth->GetValue(i);
    const signed char k = cls->GetValue(i);
    if (c.depth < 1 || c.depth > max_depth || (k != 1 && k != 2)) {
      throw Error("'" + path + "': cell " + std::to_string(i) + " has an invalid depth or class");
    }
    c.cls = static_cast<CellClass>(k);
    c.f = Interval(flo->GetValue(i), fhi->GetValue(i));
    for (int a = 0; a < 3; ++a) c.index[a] = index->GetValue(3 * i + a);
    ++enc.counts_by_depth[c.depth][k == 1 ? 0 : 1];
  }

  // Check the voxels' points against the boxes the indices describe.
  out.points_match_boxes = true;
  {
    vtkCellArray* cells = g->GetCells();
    vtkPoints* pts = g->GetPoints();
    RoundingScope scope;
    auto ids = vtkSmartPointer<vtkIdList>::New();
    for (vtkIdType i = 0; i < nc && out.points_match_boxes; ++i) {
      if (g->GetCellType(i) != VTK_VOXEL) {
        out.points_match_boxes = false;
        break;
      }
      cells->GetCellAtId(i, ids);
      const Box3 box = enc.box(enc.cells[static_cast<std::size_t>(i)]);
      for (int k = 0; k < 8; ++k) {
        double q[3];
        pts->GetPoint(ids->GetId(k), q);
        if (q[0] != ((k & 1) ? box.hi.x : box.lo.x) || q[1] != ((k & 2) ? box.hi.y : box.lo.y) ||
            q[2] != ((k & 4) ? box.hi.z : box.lo.z)) {
          out.points_match_boxes = false;
          break;
        }
      }
    }
  }
  return out;
}

}  // namespace iaa::viz
