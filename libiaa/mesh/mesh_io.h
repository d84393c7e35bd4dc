// Mesh files through OpenMesh: every mesh is held as an OpenMesh TriMesh (double precision) on its
// way in and out, and encoded or decoded with OpenMesh's readers and writers (PLY, OBJ, OFF). The
// library works on bytes in memory; reading and writing files is the tool's job. This header is
// free of OpenMesh types; the functions exist when IAA_HAVE_OPENMESH is defined.
#pragma once

#include <string>
#include <string_view>

#include "mesh/triangle_soup.h"

namespace iaa {

enum class MeshFormat { kPly, kObj, kOff };

/// The format for a file extension ("ply", "obj", "off", any case, without the dot); throws
/// iaa::Error naming the supported formats otherwise.
MeshFormat mesh_format_from_extension(std::string_view ext);

/// Encodes a mesh (ASCII with 17 significant digits, or binary PLY). Note (measured): OpenMesh
/// 9.0's writers and readers carry positions as float whatever the mesh's traits, so a file holds
/// every coordinate rounded to float; round_to_file_precision() gives the mesh a file will hold.
/// Triangles that would make an edge non-manifold are kept by giving them their own copies of the
/// vertices (as OpenMesh's own importer does); `duplicated` receives how many vertices were copied.
/// Throws iaa::Error if OpenMesh fails.
std::string encode_mesh(const TriangleSoup& mesh, MeshFormat format, bool binary = false,
                        std::size_t* duplicated = nullptr);

/// Rounds every coordinate to what a mesh file holds (float), so that a report computed on the
/// mesh describes the file exactly.
void round_to_file_precision(TriangleSoup& mesh);

/// Decodes a mesh (polygons are split into triangles). `what` names the source in errors.
/// Throws iaa::Error when OpenMesh cannot read it.
TriangleSoup decode_mesh(const std::string& bytes, MeshFormat format, const std::string& what);

}  // namespace iaa
