#include "vtkTimeSeriesWriter.h"

#include "hoembedSeriesFiles.h"

#include "vtkAlgorithmOutput.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLPolyDataWriter.h"
#include "vtkXMLUnstructuredGridWriter.h"

#include <string>
#include <vector>

vtkStandardNewMacro(vtkTimeSeriesWriter);
vtkCxxSetObjectMacro(vtkTimeSeriesWriter, TimeValues, vtkDoubleArray);

// The series' files (staging, refusals, .pvd, swap-in) are hoembed::SeriesFiles' work;
// this class writes each frame's data with VTK's XML writers into the path it gives.
struct vtkTimeSeriesWriter::Internals
{
  hoembed::SeriesFiles Files;
};

vtkTimeSeriesWriter::vtkTimeSeriesWriter() : Internal(new Internals)
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(0);
}

vtkTimeSeriesWriter::~vtkTimeSeriesWriter()
{
  // SeriesFiles' destructor abandons a series begun and never ended.
  this->SetFileName(nullptr);
  this->SetTimeValues(nullptr);
  delete this->Internal;
}

int vtkTimeSeriesWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

void vtkTimeSeriesWriter::Abandon()
{
  this->Internal->Files.Abandon();
}

int vtkTimeSeriesWriter::BeginSeries()
{
  const std::string error = this->Internal->Files.Begin(this->FileName ? this->FileName : "");
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  return 1;
}

int vtkTimeSeriesWriter::AddFrame(vtkDataObject* data, double time)
{
  hoembed::SeriesFiles& files = this->Internal->Files;
  std::string ext;
  vtkSmartPointer<vtkXMLWriter> writer;
  vtkSmartPointer<vtkDataObject> copy;
  // written from a shallow copy: the writer's pipeline must not take over the caller's
  // data object (its producer, its pipeline information)
  if (auto* ug = vtkUnstructuredGrid::SafeDownCast(data))
  {
    ext = "vtu";
    writer = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
    auto c = vtkSmartPointer<vtkUnstructuredGrid>::New();
    c->ShallowCopy(ug);
    copy = c;
  }
  else if (auto* pd = vtkPolyData::SafeDownCast(data))
  {
    ext = "vtp";
    writer = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
    auto c = vtkSmartPointer<vtkPolyData>::New();
    c->ShallowCopy(pd);
    copy = c;
  }
  std::string staged;
  std::string error = files.StartFrame(time, ext, data ? data->GetClassName() : "", staged);
  if (error.empty())
  {
    // the package's write_series (Wrapping/Python/hoembed/series.py) writes with the
    // same settings
    writer->SetInputData(copy);
    writer->SetFileName(staged.c_str());
    writer->SetDataModeToAppended();
    writer->SetCompressorTypeToZLib();
    const bool written = writer->Write() == 1 && writer->GetErrorCode() == 0;
    error = files.FinishFrame(written);
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  return 1;
}

int vtkTimeSeriesWriter::EndSeries()
{
  const std::string error = this->Internal->Files.End();
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  return 1;
}

int vtkTimeSeriesWriter::Write()
{
  vtkAlgorithm* up = this->GetNumberOfInputConnections(0) ? this->GetInputAlgorithm(0, 0) : nullptr;
  if (!up)
  {
    vtkErrorMacro("No input connection: connect an input (or use BeginSeries/AddFrame).");
    return 0;
  }
  const int port = this->GetInputConnection(0, 0)->GetIndex();
  auto* sddp = vtkStreamingDemandDrivenPipeline::SafeDownCast(up->GetExecutive());
  if (!sddp)
  {
    vtkErrorMacro("The input's executive does not support time requests.");
    return 0;
  }
  if (!sddp->UpdateInformation())
  {
    vtkErrorMacro("The input failed to provide its information.");
    return 0;
  }
  vtkInformation* outInfo = up->GetOutputInformation(port);
  std::vector<double> requested, advertised;
  if (this->TimeValues)
  {
    for (vtkIdType i = 0; i < this->TimeValues->GetNumberOfTuples(); ++i)
    {
      requested.push_back(this->TimeValues->GetValue(i));
    }
  }
  else if (outInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()))
  {
    const int n = outInfo->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    const double* t = outInfo->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    advertised.assign(t, t + n);
  }
  bool timed = false;
  const std::vector<double> times =
    hoembed::SeriesFiles::InputTimes(this->TimeValues ? &requested : nullptr,
      outInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()) ? &advertised : nullptr, timed);
  if (!this->BeginSeries())
  {
    return 0;
  }
  for (size_t k = 0; k < times.size(); ++k)
  {
    if (timed)
    {
      outInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP(), times[k]);
    }
    if (!sddp->Update(port))
    {
      vtkErrorMacro(<< hoembed::SeriesFiles::InputFailed(times[k], k));
      this->Abandon();
      return 0;
    }
    if (!this->AddFrame(up->GetOutputDataObject(port), times[k]))
    {
      return 0;
    }
    this->UpdateProgress(static_cast<double>(k + 1) / static_cast<double>(times.size()));
  }
  return this->EndSeries();
}

int vtkTimeSeriesWriter::GetNumberOfWrittenFrames()
{
  return static_cast<int>(this->Internal->Files.GetNumberOfFrames());
}

const char* vtkTimeSeriesWriter::GetFrameFileName(int i)
{
  return i < 0 ? "" : this->Internal->Files.GetFrameFileName(static_cast<std::size_t>(i)).c_str();
}

void vtkTimeSeriesWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "TimeValues: ";
  if (this->TimeValues)
  {
    os << this->TimeValues->GetNumberOfTuples() << " values\n";
  }
  else
  {
    os << "(input's TIME_STEPS)\n";
  }
}
