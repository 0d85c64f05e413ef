// vtkTimeSeriesWriter: stepper -> writer writes one .vtu per advertised time plus a .pvd;
// the files are read back with VTK's own XML readers (vtkXMLUnstructuredGridReader,
// vtkXMLPolyDataReader) and the .pvd is parsed; failures leave no .pvd behind.
#include "hoembedTestUtilities.h"

#include "vtkCommand.h"
#include "vtkCorotationalFEMStepper.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkTimeSeriesWriter.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <vtksys/SystemTools.hxx>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

namespace
{
class Quiet : public vtkCommand
{
public:
  static Quiet* New()
  {
    return new Quiet;
  }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    if (data)
      this->Text += static_cast<const char*>(data);
  }
  std::string Text;
};

std::string ReadAll(const std::string& path)
{
  std::ifstream in(path.c_str());
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
} // namespace

int main(int, char*[])
{
  const std::string dir = vtksys::SystemTools::GetCurrentWorkingDirectory() + "/tsw_test";
  vtksys::SystemTools::RemoveADirectory(dir);

  // Pipeline mode: stepper over its 4 advertised times.
  auto mesh = hoembed_test::MakeBoxTetMesh(3, 1, 1, 3.0, 1.0, 1.0, 2);
  vtkNew<vtkCorotationalFEMStepper> stepper;
  stepper->SetInputData(mesh);
  stepper->UseClampPlaneOn();
  stepper->SetYoungModulus(1e6);
  stepper->SetTimeStep(0.05);
  stepper->SetNumberOfTimeSteps(3);
  vtkNew<vtkTimeSeriesWriter> writer;
  writer->SetInputConnection(stepper->GetOutputPort());
  writer->SetFileName((dir + "/beam.pvd").c_str());
  HOEMBED_CHECK(writer->Write() == 1, "pipeline series not written");
  HOEMBED_CHECK(writer->GetNumberOfWrittenFrames() == 4, "%d frames written",
    writer->GetNumberOfWrittenFrames());
  const std::string pvd = ReadAll(dir + "/beam.pvd");
  HOEMBED_CHECK(pvd.find("type=\"Collection\"") != std::string::npos, "no Collection in pvd");
  HOEMBED_CHECK(pvd.find("timestep=\"0.10000000000000001\" group=\"\" part=\"0\" "
                         "file=\"beam/beam_000002.vtu\"") != std::string::npos,
    "pvd entry for t = 0.1 missing:\n%s", pvd.c_str());
  // Each file holds the stepper's output at its time: compare with a direct request.
  for (int k = 0; k < 4; ++k)
  {
    vtkNew<vtkXMLUnstructuredGridReader> r;
    r->SetFileName(writer->GetFrameFileName(k));
    r->Update();
    vtkUnstructuredGrid* g = r->GetOutput();
    stepper->UpdateTimeStep(0.05 * k);
    vtkDataArray* a = g->GetPointData()->GetArray("Displacement");
    vtkDataArray* b = stepper->GetOutput()->GetPointData()->GetArray("Displacement");
    HOEMBED_CHECK(a && b && g->GetNumberOfCells() == mesh->GetNumberOfCells(),
      "frame %d unreadable or wrong", k);
    if (a && b)
    {
      double diff = 0.0;
      for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
        for (int c = 0; c < 3; ++c)
          diff = std::max(diff, std::abs(a->GetComponent(i, c) - b->GetComponent(i, c)));
      HOEMBED_CHECK(
        diff == 0.0, "frame %d differs from the stepper at t = %g by %g", k, 0.05 * k, diff);
      HOEMBED_CHECK(k == 0 || a->GetRange(2)[0] < 0.0, "frame %d shows no sagging", k);
    }
  }
  HOEMBED_CHECK(!vtksys::SystemTools::FileExists(dir + "/beam.pvd.part"), "temp pvd left over");

  // Frames mode with poly data and explicit times.
  vtkNew<vtkSphereSource> sphere;
  sphere->Update();
  vtkNew<vtkTimeSeriesWriter> fw;
  fw->SetFileName((dir + "/surf.pvd").c_str());
  HOEMBED_CHECK(fw->BeginSeries() == 1, "BeginSeries failed");
  HOEMBED_CHECK(fw->AddFrame(sphere->GetOutput(), 0.25) == 1, "AddFrame failed");
  HOEMBED_CHECK(fw->EndSeries() == 1, "EndSeries failed");
  vtkNew<vtkXMLPolyDataReader> pr;
  pr->SetFileName((dir + "/surf/surf_000000.vtp").c_str());
  pr->Update();
  HOEMBED_CHECK(pr->GetOutput()->GetNumberOfPoints() == sphere->GetOutput()->GetNumberOfPoints(),
    "vtp frame has %lld points", static_cast<long long>(pr->GetOutput()->GetNumberOfPoints()));

  // Failures leave no .pvd: unsupported type, and a failing input.
  vtkNew<Quiet> quiet;
  vtkNew<vtkTimeSeriesWriter> bad;
  bad->AddObserver(vtkCommand::ErrorEvent, quiet);
  bad->SetFileName((dir + "/bad.pvd").c_str());
  bad->BeginSeries();
  bad->AddFrame(sphere->GetOutput(), 0.0);
  vtkNew<vtkImageData> image;
  HOEMBED_CHECK(bad->AddFrame(image, 1.0) == 0, "image data accepted");
  HOEMBED_CHECK(quiet->Text.find("unsupported data type") != std::string::npos, "message: %s",
    quiet->Text.c_str());
  HOEMBED_CHECK(!vtksys::SystemTools::FileExists(dir + "/bad.pvd") &&
      !vtksys::SystemTools::FileExists(dir + "/bad/bad_000000.vtp"),
    "abandoned series left files");

  vtkNew<vtkCorotationalFEMStepper> failing;
  failing->SetInputData(mesh);
  failing->SetDensity(-1.0);
  failing->AddObserver(vtkCommand::ErrorEvent, quiet);
  failing->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, quiet);
  vtkNew<vtkTimeSeriesWriter> fw2;
  fw2->AddObserver(vtkCommand::ErrorEvent, quiet);
  fw2->SetInputConnection(failing->GetOutputPort());
  fw2->SetFileName((dir + "/fail.pvd").c_str());
  HOEMBED_CHECK(fw2->Write() == 0, "failing input did not fail the writer");
  HOEMBED_CHECK(!vtksys::SystemTools::FileExists(dir + "/fail.pvd"), "failed series has a pvd");

  vtksys::SystemTools::RemoveADirectory(dir);
  return hoembed_test::Report("TestTimeSeriesWriter");
}
