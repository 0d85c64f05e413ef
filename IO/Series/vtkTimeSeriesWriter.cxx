#include "vtkTimeSeriesWriter.h"

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

#include <vtksys/Directory.hxx>
#include <vtksys/SystemTools.hxx>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTimeSeriesWriter);
vtkCxxSetObjectMacro(vtkTimeSeriesWriter, TimeValues, vtkDoubleArray);

struct vtkTimeSeriesWriter::Internals
{
  bool Open = false;
  std::string Pvd, Folder, Staging, Stem, RelFolder;
  std::vector<std::string> Files; // final paths
  std::vector<std::string> Relative;
  std::vector<double> Times;
};

namespace
{
// A step file this writer may replace: `<stem>_NNNNNN.vtu` / `.vtp` (or such a name
// with `.part`, left by writers before the staging folder).
bool IsStepFile(const std::string& name, const std::string& stem)
{
  if (name.size() < stem.size() + 11 || name.compare(0, stem.size(), stem) != 0 ||
    name[stem.size()] != '_')
  {
    return false;
  }
  size_t k = stem.size() + 1;
  for (int d = 0; d < 6; ++d, ++k)
  {
    if (name[k] < '0' || name[k] > '9')
    {
      return false;
    }
  }
  const std::string rest = name.substr(k);
  return rest == ".vtu" || rest == ".vtp" || rest == ".vtu.part" || rest == ".vtp.part";
}
} // namespace

vtkTimeSeriesWriter::vtkTimeSeriesWriter()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(0);
}

vtkTimeSeriesWriter::~vtkTimeSeriesWriter()
{
  // A series begun and never ended must not leave its frames behind.
  if (this->Internal->Open)
  {
    this->Abandon();
  }
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
  Internals& I = *this->Internal;
  if (!I.Staging.empty())
  {
    vtksys::SystemTools::RemoveADirectory(I.Staging);
  }
  if (!I.Pvd.empty())
  {
    vtksys::SystemTools::RemoveFile(I.Pvd + ".part");
  }
  I.Files.clear();
  I.Relative.clear();
  I.Times.clear();
  I.Open = false;
}

int vtkTimeSeriesWriter::BeginSeries()
{
  Internals& I = *this->Internal;
  if (I.Open)
  {
    this->Abandon();
  }
  I.Files.clear();
  I.Relative.clear();
  I.Times.clear();
  I.Staging.clear();
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("FileName (the .pvd path) is not set.");
    return 0;
  }
  I.Pvd = this->FileName;
  std::string dir = vtksys::SystemTools::GetFilenamePath(I.Pvd);
  I.Stem = vtksys::SystemTools::GetFilenameWithoutLastExtension(
    vtksys::SystemTools::GetFilenameName(I.Pvd));
  if (I.Stem.empty() || I.Stem[0] == '.')
  {
    vtkErrorMacro("FileName '" << this->FileName << "' has no file name (or starts with '.').");
    return 0;
  }
  I.RelFolder = I.Stem;
  I.Folder = dir.empty() ? I.Stem : dir + "/" + I.Stem;
  I.Staging = (dir.empty() ? std::string() : dir + "/") + "." + I.Stem + ".staging";
  if (vtksys::SystemTools::FileIsDirectory(I.Pvd))
  {
    vtkErrorMacro("Cannot write the series '" << I.Pvd << "': that path is a folder.");
    I.Staging.clear();
    return 0;
  }
  if (vtksys::SystemTools::FileExists(I.Folder) &&
    !vtksys::SystemTools::FileIsDirectory(I.Folder))
  {
    vtkErrorMacro("Cannot write the series '" << I.Pvd << "': its step folder '" << I.Folder
                                              << "' is a file.");
    I.Staging.clear();
    return 0;
  }
  if (vtksys::SystemTools::FileIsDirectory(I.Folder))
  {
    vtksys::Directory listing;
    if (!listing.Load(I.Folder))
    {
      vtkErrorMacro("Cannot read the step folder '" << I.Folder << "'.");
      I.Staging.clear();
      return 0;
    }
    for (unsigned long k = 0; k < listing.GetNumberOfFiles(); ++k)
    {
      const std::string name = listing.GetFile(k);
      if (name != "." && name != ".." && !IsStepFile(name, I.Stem))
      {
        vtkErrorMacro("Cannot write the series '"
          << I.Pvd << "': its step folder '" << I.Folder << "' holds '" << name
          << "', which is not a step file of this series (the folder is replaced as a "
             "whole, so it must hold nothing else).");
        I.Staging.clear();
        return 0;
      }
    }
  }
  if (!dir.empty() && !vtksys::SystemTools::FileIsDirectory(dir) &&
    !vtksys::SystemTools::MakeDirectory(dir).IsSuccess())
  {
    vtkErrorMacro("Cannot create the folder '" << dir << "'.");
    I.Staging.clear();
    return 0;
  }
  // A staging folder left by a process that died mid-series is ours to clear.
  vtksys::SystemTools::RemoveADirectory(I.Staging);
  if (!vtksys::SystemTools::MakeDirectory(I.Staging).IsSuccess())
  {
    vtkErrorMacro("Cannot create the folder '" << I.Staging << "'.");
    I.Staging.clear();
    return 0;
  }
  I.Open = true;
  return 1;
}

int vtkTimeSeriesWriter::AddFrame(vtkDataObject* data, double time)
{
  Internals& I = *this->Internal;
  if (!I.Open)
  {
    vtkErrorMacro("AddFrame called outside BeginSeries()/EndSeries().");
    return 0;
  }
  if (!std::isfinite(time))
  {
    vtkErrorMacro("Frame " << I.Files.size() << ": the time is " << time
                           << " (a finite time is needed).");
    this->Abandon();
    return 0;
  }
  const char* ext = nullptr;
  vtkSmartPointer<vtkXMLWriter> writer;
  vtkSmartPointer<vtkDataObject> copy;
  if (auto* ug = vtkUnstructuredGrid::SafeDownCast(data))
  {
    ext = "vtu";
    auto w = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
    auto c = vtkSmartPointer<vtkUnstructuredGrid>::New();
    c->ShallowCopy(ug);
    copy = c;
    writer = w;
  }
  else if (auto* pd = vtkPolyData::SafeDownCast(data))
  {
    ext = "vtp";
    auto w = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
    auto c = vtkSmartPointer<vtkPolyData>::New();
    c->ShallowCopy(pd);
    copy = c;
    writer = w;
  }
  else
  {
    vtkErrorMacro("Frame " << I.Files.size() << ": unsupported data type "
                           << (data ? data->GetClassName() : "(null)")
                           << " (vtkUnstructuredGrid or vtkPolyData expected).");
    this->Abandon();
    return 0;
  }
  std::ostringstream name;
  name << I.Stem << "_" << std::setw(6) << std::setfill('0') << I.Files.size() << "." << ext;
  const std::string staged = I.Staging + "/" + name.str();
  writer->SetInputData(copy);
  writer->SetFileName(staged.c_str());
  writer->SetDataModeToAppended();
  writer->SetCompressorTypeToZLib();
  if (writer->Write() != 1 || writer->GetErrorCode() != 0)
  {
    vtkErrorMacro("Frame " << I.Files.size() << " (t = " << time << "): cannot write '"
                           << staged << "'.");
    this->Abandon();
    return 0;
  }
  I.Files.push_back(I.Folder + "/" + name.str());
  I.Relative.push_back(I.RelFolder + "/" + name.str());
  I.Times.push_back(time);
  return 1;
}

int vtkTimeSeriesWriter::EndSeries()
{
  Internals& I = *this->Internal;
  if (!I.Open)
  {
    vtkErrorMacro("EndSeries called without BeginSeries().");
    return 0;
  }
  if (I.Files.empty())
  {
    vtkErrorMacro("The series has no frames: nothing written.");
    this->Abandon();
    return 0;
  }
  const std::string part = I.Pvd + ".part";
  {
    std::ofstream out(part.c_str(), std::ios::out | std::ios::trunc);
    if (!out)
    {
      vtkErrorMacro("Cannot write '" << part << "'.");
      this->Abandon();
      return 0;
    }
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <Collection>\n";
    out << std::setprecision(17);
    for (size_t i = 0; i < I.Relative.size(); ++i)
    {
      out << "    <DataSet timestep=\"" << I.Times[i] << "\" group=\"\" part=\"0\" file=\""
          << I.Relative[i] << "\"/>\n";
    }
    out << "  </Collection>\n</VTKFile>\n";
    out.close();
    if (!out)
    {
      vtkErrorMacro("Cannot write '" << part << "'.");
      this->Abandon();
      return 0;
    }
  }
  // Swap in: old step folder aside, staging folder in its place, .pvd renamed over the
  // old one (atomic), old folder removed. Any failure puts the old folder back.
  const std::string aside = I.Staging + ".old";
  vtksys::SystemTools::RemoveADirectory(aside);
  const bool hadOld = vtksys::SystemTools::FileIsDirectory(I.Folder);
  if (hadOld && std::rename(I.Folder.c_str(), aside.c_str()) != 0)
  {
    vtkErrorMacro("Cannot move the old step folder '" << I.Folder << "' aside.");
    this->Abandon();
    return 0;
  }
  if (std::rename(I.Staging.c_str(), I.Folder.c_str()) != 0)
  {
    vtkErrorMacro("Cannot rename '" << I.Staging << "' to '" << I.Folder << "'.");
    if (hadOld)
    {
      std::rename(aside.c_str(), I.Folder.c_str());
    }
    this->Abandon();
    return 0;
  }
  if (std::rename(part.c_str(), I.Pvd.c_str()) != 0)
  {
    vtkErrorMacro("Cannot rename '" << part << "' to '" << I.Pvd << "'.");
    std::rename(I.Folder.c_str(), I.Staging.c_str());
    if (hadOld)
    {
      std::rename(aside.c_str(), I.Folder.c_str());
    }
    this->Abandon();
    return 0;
  }
  if (hadOld)
  {
    vtksys::SystemTools::RemoveADirectory(aside);
  }
  I.Staging.clear();
  I.Open = false;
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
  std::vector<double> times;
  bool timed = false;
  if (this->TimeValues)
  {
    for (vtkIdType i = 0; i < this->TimeValues->GetNumberOfTuples(); ++i)
    {
      times.push_back(this->TimeValues->GetValue(i));
    }
    timed = true;
  }
  else if (outInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()))
  {
    const int n = outInfo->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    const double* t = outInfo->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    times.assign(t, t + n);
    timed = true;
  }
  if (times.empty())
  {
    times.push_back(0.0);
  }
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
      vtkErrorMacro("The input failed at time " << times[k] << " (step " << k << ").");
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
  return static_cast<int>(this->Internal->Files.size());
}

const char* vtkTimeSeriesWriter::GetFrameFileName(int i)
{
  if (i < 0 || i >= static_cast<int>(this->Internal->Files.size()))
  {
    return "";
  }
  return this->Internal->Files[i].c_str();
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
