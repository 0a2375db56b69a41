// A scene file as a document: read, its materials' parameter sets inspected and replaced, written
// back. loadSceneDescription builds the scene from one; `btf fit-scene` writes its lean scene
// through one (the measured materials swapped for smaller forms).
//
// File names. Every relative file name in a document (a material's "file" and "fits_dir", a
// shape's or an environment's "file") resolves against the folder of the document's file. A
// material set in with setMaterial keeps pointing where its own parameters pointed (relative names
// there resolve against their origin's folder, the current directory for a set made in code), and
// write() rewrites relative names for the folder of the file written, so that a scene written
// elsewhere still finds its meshes and materials. Absolute names stay as they are.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "btf/material/material_params.h"

namespace btf::render {

class SceneDocument {
 public:
  // Throws FileError for a missing file or one that is not JSON; the rest is checked by
  // loadSceneDescription.
  static SceneDocument read(const std::filesystem::path& file);
  ~SceneDocument();
  SceneDocument(const SceneDocument&);
  SceneDocument& operator=(const SceneDocument&);
  SceneDocument(SceneDocument&&) noexcept;
  SceneDocument& operator=(SceneDocument&&) noexcept;

  const std::filesystem::path& file() const;
  // The names under "materials", in the file's order of keys (sorted).
  std::vector<std::string> materialNames() const;
  bool hasMaterial(const std::string& name) const;
  // The parameter set of a material; its origin is the scene file. Throws FileError for an
  // unknown name.
  MaterialParams material(const std::string& name) const;
  void setMaterial(const std::string& name, const MaterialParams& params);
  void setComment(const std::string& comment);

  // The document as a scene file at `path` (temporary file, then rename), file names rewritten
  // for its folder (see above).
  void write(const std::filesystem::path& path) const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  explicit SceneDocument(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace btf::render
