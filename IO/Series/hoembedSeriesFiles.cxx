#include "hoembedSeriesFiles.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <system_error>

namespace fs = std::filesystem;

namespace hoembed
{
namespace
{
// The path operations as vtksys::SystemTools did them for this writer (which the
// messages and the layout were defined with): the folder is everything before the last
// '/', the stem the file name without its last extension.
std::string FolderOf(const std::string& path)
{
  const std::size_t slash = path.rfind('/');
  if (slash == std::string::npos)
  {
    return std::string();
  }
  return slash == 0 ? std::string("/") : path.substr(0, slash);
}

std::string StemOf(const std::string& path)
{
  const std::size_t slash = path.rfind('/');
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::size_t dot = name.rfind('.');
  return dot == std::string::npos ? name : name.substr(0, dot);
}

std::string Join(const std::string& folder, const std::string& name)
{
  if (folder.empty())
  {
    return name;
  }
  return folder.back() == '/' ? folder + name : folder + "/" + name;
}

bool IsFolder(const std::string& path)
{
  std::error_code ec;
  return fs::is_directory(path, ec);
}

bool Exists(const std::string& path)
{
  std::error_code ec;
  return fs::exists(path, ec);
}

// Removes a folder and what it holds; a missing one is fine.
void RemoveFolder(const std::string& path)
{
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(path, ec)))
  {
    fs::remove_all(path, ec);
  }
}

void RemoveFile(const std::string& path)
{
  std::error_code ec;
  fs::remove(path, ec);
}

bool MakeFolder(const std::string& path)
{
  std::error_code ec;
  fs::create_directories(path, ec);
  return IsFolder(path);
}
} // namespace

SeriesFiles::~SeriesFiles()
{
  // A series begun and never ended must not leave its frames behind.
  if (this->Open)
  {
    this->Abandon();
  }
}

bool SeriesFiles::IsStepFile(const std::string& name, const std::string& stem)
{
  if (name.size() < stem.size() + 11 || name.compare(0, stem.size(), stem) != 0 ||
    name[stem.size()] != '_')
  {
    return false;
  }
  std::size_t k = stem.size() + 1;
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

std::string SeriesFiles::FrameName(
  const std::string& stem, std::size_t index, const std::string& extension)
{
  std::ostringstream name;
  name << stem << "_" << std::setw(6) << std::setfill('0') << index << "." << extension;
  return name.str();
}

std::vector<double> SeriesFiles::InputTimes(
  const std::vector<double>* requested, const std::vector<double>* advertised, bool& timed)
{
  std::vector<double> times;
  timed = requested || advertised;
  if (requested)
  {
    times = *requested;
  }
  else if (advertised)
  {
    times = *advertised;
  }
  if (times.empty())
  {
    times.push_back(0.0);
  }
  return times;
}

std::string SeriesFiles::InputFailed(double time, std::size_t step)
{
  std::ostringstream msg;
  msg << "The input failed at time " << time << " (step " << step << ").";
  return msg.str();
}

std::string SeriesFiles::CollectionText(
  const std::vector<double>& times, const std::vector<std::string>& relativePaths)
{
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  // 17 digits: a time read back from the .pvd is the double that was written
  out << std::setprecision(17);
  for (std::size_t i = 0; i < relativePaths.size() && i < times.size(); ++i)
  {
    out << "    <DataSet timestep=\"" << times[i] << "\" group=\"\" part=\"0\" file=\""
        << relativePaths[i] << "\"/>\n";
  }
  out << "  </Collection>\n</VTKFile>\n";
  return out.str();
}

const std::string& SeriesFiles::GetFrameFileName(std::size_t i) const
{
  static const std::string none;
  return i < this->Files.size() ? this->Files[i] : none;
}

void SeriesFiles::Abandon()
{
  if (!this->Staging.empty())
  {
    RemoveFolder(this->Staging);
  }
  if (!this->Pvd.empty())
  {
    RemoveFile(this->Pvd + ".part");
  }
  this->Files.clear();
  this->Relative.clear();
  this->Times.clear();
  this->Pending = false;
  this->Open = false;
}

std::string SeriesFiles::Begin(const std::string& pvdPath)
{
  if (this->Open)
  {
    this->Abandon();
  }
  this->Files.clear();
  this->Relative.clear();
  this->Times.clear();
  this->Staging.clear();
  this->Pending = false;
  if (pvdPath.empty())
  {
    this->Pvd.clear();
    return "FileName (the .pvd path) is not set.";
  }
  this->Pvd = pvdPath;
  const std::string dir = FolderOf(pvdPath);
  this->Stem = StemOf(pvdPath);
  if (this->Stem.empty() || this->Stem[0] == '.')
  {
    return "FileName '" + pvdPath + "' has no file name (or starts with '.').";
  }
  this->Folder = Join(dir, this->Stem);
  const std::string staging = Join(dir, "." + this->Stem + ".staging");
  const std::string series = "Cannot write the series '" + pvdPath + "': ";
  if (IsFolder(pvdPath))
  {
    return series + "that path is a folder.";
  }
  if (Exists(this->Folder) && !IsFolder(this->Folder))
  {
    return series + "its step folder '" + this->Folder + "' is a file.";
  }
  if (IsFolder(this->Folder))
  {
    std::error_code ec;
    fs::directory_iterator it(this->Folder, ec);
    if (ec)
    {
      return "Cannot read the step folder '" + this->Folder + "'.";
    }
    for (; it != fs::directory_iterator(); it.increment(ec))
    {
      const std::string name = it->path().filename().string();
      if (!IsStepFile(name, this->Stem))
      {
        return series + "its step folder '" + this->Folder + "' holds '" + name +
          "', which is not a step file of this series (the folder is replaced as a whole, "
          "so it must hold nothing else).";
      }
    }
    if (ec)
    {
      return "Cannot read the step folder '" + this->Folder + "'.";
    }
  }
  if (!dir.empty() && !IsFolder(dir) && !MakeFolder(dir))
  {
    return "Cannot create the folder '" + dir + "'.";
  }
  // A staging folder left by a process that died mid-series is ours to clear.
  RemoveFolder(staging);
  std::error_code ec;
  if (!fs::create_directory(staging, ec) || ec)
  {
    return "Cannot create the folder '" + staging + "'.";
  }
  this->Staging = staging;
  this->Open = true;
  return std::string();
}

std::string SeriesFiles::StartFrame(
  double time, const std::string& extension, const std::string& dataType, std::string& staged)
{
  staged.clear();
  if (!this->Open)
  {
    return "AddFrame called outside BeginSeries()/EndSeries().";
  }
  std::ostringstream error;
  error << "Frame " << this->Files.size();
  if (!std::isfinite(time))
  {
    error << ": the time is " << time << " (a finite time is needed).";
    this->Abandon();
    return error.str();
  }
  if (extension != "vtu" && extension != "vtp")
  {
    error << ": unsupported data type " << (dataType.empty() ? "(null)" : dataType)
          << " (vtkUnstructuredGrid or vtkPolyData expected).";
    this->Abandon();
    return error.str();
  }
  this->PendingName = FrameName(this->Stem, this->Files.size(), extension);
  this->PendingStaged = this->Staging + "/" + this->PendingName;
  this->PendingTime = time;
  this->Pending = true;
  staged = this->PendingStaged;
  return std::string();
}

std::string SeriesFiles::FinishFrame(bool written)
{
  if (!this->Open || !this->Pending)
  {
    return "AddFrame called outside BeginSeries()/EndSeries().";
  }
  this->Pending = false;
  if (!written)
  {
    std::ostringstream error;
    error << "Frame " << this->Files.size() << " (t = " << this->PendingTime << "): cannot write '"
          << this->PendingStaged << "'.";
    this->Abandon();
    return error.str();
  }
  this->Files.push_back(this->Folder + "/" + this->PendingName);
  this->Relative.push_back(this->Stem + "/" + this->PendingName);
  this->Times.push_back(this->PendingTime);
  return std::string();
}

std::string SeriesFiles::End()
{
  if (!this->Open)
  {
    return "EndSeries called without BeginSeries().";
  }
  if (this->Files.empty())
  {
    this->Abandon();
    return "The series has no frames: nothing written.";
  }
  const std::string part = this->Pvd + ".part";
  {
    std::ofstream out(part.c_str(), std::ios::out | std::ios::trunc | std::ios::binary);
    if (out)
    {
      out << CollectionText(this->Times, this->Relative);
      out.close();
    }
    if (!out)
    {
      this->Abandon();
      return "Cannot write '" + part + "'.";
    }
  }
  // Swap in: old step folder aside, staging folder in its place, .pvd renamed over the
  // old one (atomic), old folder removed. Any failure puts the old folder back.
  const std::string aside = this->Staging + ".old";
  RemoveFolder(aside);
  const bool hadOld = IsFolder(this->Folder);
  if (hadOld && std::rename(this->Folder.c_str(), aside.c_str()) != 0)
  {
    this->Abandon();
    return "Cannot move the old step folder '" + this->Folder + "' aside.";
  }
  if (std::rename(this->Staging.c_str(), this->Folder.c_str()) != 0)
  {
    const std::string error = "Cannot rename '" + this->Staging + "' to '" + this->Folder + "'.";
    if (hadOld)
    {
      std::rename(aside.c_str(), this->Folder.c_str());
    }
    this->Abandon();
    return error;
  }
  if (std::rename(part.c_str(), this->Pvd.c_str()) != 0)
  {
    const std::string error = "Cannot rename '" + part + "' to '" + this->Pvd + "'.";
    std::rename(this->Folder.c_str(), this->Staging.c_str());
    if (hadOld)
    {
      std::rename(aside.c_str(), this->Folder.c_str());
    }
    this->Abandon();
    return error;
  }
  if (hadOld)
  {
    RemoveFolder(aside);
  }
  this->Staging.clear();
  this->Open = false;
  return std::string();
}
} // namespace hoembed
