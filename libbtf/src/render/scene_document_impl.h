// The JSON behind a SceneDocument, for the loader in this layer.
#pragma once

#include "btf/render/scene_document.h"
#include "json_node.h"

namespace btf::render {

struct SceneDocument::Impl {
  std::filesystem::path file;
  detail::json root;
};

}  // namespace btf::render
