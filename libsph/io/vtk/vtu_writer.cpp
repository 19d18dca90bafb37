#include "libsph/io/vtk/vtu_writer.hpp"

#include <stdexcept>

#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPUnstructuredGridWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>
#ifdef CARDIOSPH_VTK_MPI
#include <vtkMPIController.h>
#endif

#include "libsph/io/atomic_file.hpp"

namespace sph {

bool vtu_output_available() { return true; }

namespace {

vtkSmartPointer<vtkUnstructuredGrid> vertex_grid(const std::vector<double>& points_xyz, const std::vector<PointArray>& arrays) {
  const vtkIdType n = static_cast<vtkIdType>(points_xyz.size() / 3);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i) points->SetPoint(i, &points_xyz[3 * static_cast<std::size_t>(i)]);

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->Allocate(n);
  for (vtkIdType i = 0; i < n; ++i) grid->InsertNextCell(VTK_VERTEX, 1, &i);

  for (const auto& array : arrays) {
    if (array.values.size() != static_cast<std::size_t>(n) * static_cast<std::size_t>(array.n_components))
      throw std::logic_error("vtu output: array '" + array.name + "' has the wrong size");
    vtkNew<vtkDoubleArray> data;
    data->SetName(array.name.c_str());
    data->SetNumberOfComponents(array.n_components);
    data->SetNumberOfTuples(n);
    std::copy(array.values.begin(), array.values.end(), data->GetPointer(0));
    grid->GetPointData()->AddArray(data);
  }
  return grid;
}

}  // namespace

void write_vtu(const std::filesystem::path& path, const std::vector<double>& points_xyz,
               const std::vector<PointArray>& arrays) {
  write_unstructured_grid(*vertex_grid(points_xyz, arrays), path);
}

void write_vtu_piece(const std::filesystem::path& summary, int piece, int pieces, const std::vector<double>& points_xyz,
                     const std::vector<PointArray>& arrays) {
#ifdef CARDIOSPH_VTK_MPI
  // VTK's controller on the MPI_COMM_WORLD that MpiSession started (never deleted: it must not
  // outlive MPI_Finalize in a static destructor).
  static vtkMPIController* const controller = [] {
    vtkMPIController* c = vtkMPIController::New();
    c->Initialize(nullptr, nullptr, 1);
    return c;
  }();
#else
  if (pieces > 1)
    throw std::runtime_error("cannot write '" + summary.string() + "' in pieces: this build's VTK has no MPI (VTK::ParallelMPI)");
#endif
  const auto grid = vertex_grid(points_xyz, arrays);
  vtkNew<vtkXMLPUnstructuredGridWriter> writer;
#ifdef CARDIOSPH_VTK_MPI
  writer->SetController(controller);
#endif
  writer->SetFileName(summary.string().c_str());
  writer->SetInputData(grid);
  writer->SetNumberOfPieces(pieces);
  writer->SetStartPiece(piece);
  writer->SetEndPiece(piece);
  writer->SetWriteSummaryFile(1);  // collective with the controller: rank 0 alone writes it
  writer->SetUseSubdirectory(true);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToZLib();
  if (writer->Write() != 1) throw std::runtime_error("cannot write piece " + std::to_string(piece) + " of '" + summary.string() + "'");
}

void write_unstructured_grid(vtkUnstructuredGrid& grid, const std::filesystem::path& path) {
  const auto temporary = temporary_path_for(path);
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(temporary.string().c_str());
  writer->SetInputData(&grid);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToZLib();
  if (writer->Write() != 1) throw std::runtime_error("cannot write '" + temporary.string() + "'");
  commit_temporary(temporary, path);
}

}  // namespace sph
