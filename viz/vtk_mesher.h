// The everyday baseline mesher: VTK's vtkSampleFunction over our point evaluator on a regular
// grid, contoured at 0 with vtkFlyingEdges3D. Point samples only: anything thinner than the grid
// spacing between two samples of the same sign is lost without a trace. Returns a plain triangle
// soup (no VTK or OpenMesh types in this header).
#pragma once

#include "app/meshing.h"
#include "core/exec.h"
#include "core/vec.h"
#include "expr/tape.h"
#include "mesh/triangle_soup.h"

namespace iaa::viz {

struct VtkMeshSettings {
  Box3 bounds;
  /// Grid cells per axis (samples are grid + 1 per axis), 2..2048.
  int grid = 128;
  /// Throws SettingError naming the setting and its limits.
  void validate() const;
};

/// Samples f on the grid (threads from exec; undefined points count as positive) and extracts
/// f = 0 with flying edges. Triangles are oriented with normals towards increasing f.
TriangleSoup mesh_vtk(const Tape& tape, const VtkMeshSettings& settings, const Exec& exec = {});

/// mesh_vtk as the application layer's meshers run (app::meshing::VtkMesher): on a grid of
/// `p.grid` (else `p.resolution`) cells per axis, timed, with its settings in the run's details.
void run_vtk_mesher(const app::meshing::Surface& s, const app::meshing::MeshParams& p,
                    const Exec& exec, app::meshing::MeshRun& run);

}  // namespace iaa::viz
