#include "libsph/io/vtk/vtu_writer.hpp"

#include <stdexcept>

#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "libsph/io/atomic_file.hpp"

namespace sph {

bool vtu_output_available() { return true; }

void write_vtu(const std::filesystem::path& path, const std::vector<double>& points_xyz,
               const std::vector<PointArray>& arrays) {
  const vtkIdType n = static_cast<vtkIdType>(points_xyz.size() / 3);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i) points->SetPoint(i, &points_xyz[3 * static_cast<std::size_t>(i)]);

  vtkNew<vtkUnstructuredGrid> grid;
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

  write_unstructured_grid(*grid, path);
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
