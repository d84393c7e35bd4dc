// viz/enclosure_pvtu.h.
#include "viz/enclosure_pvtu.h"

#include <filesystem>

#include <vtkObjectFactory.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPUnstructuredGridWriter.h>

#include "core/error.h"

namespace iaa::viz {

namespace {

/// VTK's parallel writer, whose summary names every piece. Without a vtkMultiProcessController
/// (iaa's processes talk through libiaa/dist, not VTK) the summary would name only the pieces
/// this process wrote; the caller writes the summary once every process has written its piece.
class EveryPieceWriter : public vtkXMLPUnstructuredGridWriter {
 public:
  static EveryPieceWriter* New();
  vtkTypeMacro(EveryPieceWriter, vtkXMLPUnstructuredGridWriter)

      protected : void PrepareSummaryFile() override {
    vtkXMLPUnstructuredGridWriter::PrepareSummaryFile();
    for (int i = 0; i < NumberOfPieces; ++i) PieceWrittenFlags[i] = 1;
  }
};
vtkStandardNewMacro(EveryPieceWriter);

}  // namespace

void write_enclosure_pvtu(const std::string& path, const Enclosure& enc, const EnclosureInfo& info,
                          int piece, int pieces, bool summary) {
  IAA_CHECK(pieces >= 1 && piece >= 0 && piece < pieces);
  const std::size_t n = enc.cells.size();
  const std::size_t begin = n * std::size_t(piece) / std::size_t(pieces);
  const std::size_t end = n * std::size_t(piece + 1) / std::size_t(pieces);
  Enclosure slice;
  slice.bounds = enc.bounds;
  slice.evaluations = enc.evaluations;
  slice.corner_evaluations = enc.corner_evaluations;
  slice.expansion_signs = enc.expansion_signs;
  slice.counts_by_depth = enc.counts_by_depth;
  slice.cells.assign(enc.cells.begin() + std::ptrdiff_t(begin),
                     enc.cells.begin() + std::ptrdiff_t(end));

  auto writer = vtkSmartPointer<EveryPieceWriter>::New();
  writer->SetFileName(path.c_str());
  writer->SetInputData(enclosure_to_grid(slice, info));
  writer->SetNumberOfPieces(pieces);
  writer->SetStartPiece(piece);
  writer->SetEndPiece(piece);
  writer->SetWriteSummaryFile(summary ? 1 : 0);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToLZ4();
  writer->SetCompressionLevel(1);
  writer->SetHeaderTypeToUInt64();
  if (slice.cells.size() < (std::size_t{1} << 27)) writer->SetIdTypeToInt32();
  if (writer->Write() != 1 || writer->GetErrorCode() != 0) {
    throw Error("cannot write '" + path + "' (piece " + std::to_string(piece) +
                "): the VTK writer failed");
  }
}

}  // namespace iaa::viz
