#include "app/organ_actors.h"

#include <vtkCellArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkTexture.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "haptics/setup/albedo_texture.h"

namespace lap::app {
namespace {

// The image as a texture, uploaded once by the renderer. Row 0 of the image data is texture
// coordinate t = 0, which is glTF's v = 0 (the image's top row), so the rows go in as stored.
vtkSmartPointer<vtkTexture> make_texture(const haptics::RgbImage& image) {
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* out = static_cast<unsigned char*>(data->GetScalarPointer());
  std::memcpy(out, image.rgb.data(), image.rgb.size());
  auto texture = vtkSmartPointer<vtkTexture>::New();
  texture->SetInputData(data);
  texture->InterpolateOn();
  texture->MipmapOn();
  texture->RepeatOn();
  return texture;
}

// For an organ without a colour texture (an OBJ stand-in): a tileable mottling of its colour,
// bright and dark by ±25 % (fractal value noise, haptics/setup/albedo_texture.h), so that its
// surface reads as tissue rather than plastic; its hue is the scenario's colour throughout.
haptics::RgbImage mottled(const Eigen::Vector3d& colour) {
  constexpr int32_t kSize = 128;
  haptics::RgbImage image;
  image.width = kSize;
  image.height = kSize;
  image.rgb.resize(static_cast<size_t>(kSize) * kSize * 3);
  for (int32_t y = 0; y < kSize; ++y) {
    for (int32_t x = 0; x < kSize; ++x) {
      const double f = haptics::tileable_fbm((x + 0.5) / kSize, (y + 0.5) / kSize, 8, 4, 7);
      const double gain = 0.75 + 0.5 * f;
      for (int c = 0; c < 3; ++c) {
        image.rgb[(static_cast<size_t>(y) * kSize + x) * 3 + static_cast<size_t>(c)] =
            static_cast<uint8_t>(std::clamp(255.0 * colour[c] * gain, 0.0, 255.0));
      }
    }
  }
  return image;
}

// Texture coordinates for a mesh that has none: round a vertical axis through its centroid
// (the angle mirrored, so the coordinates run on without a seam) and up it, one image per 2 cm.
std::vector<Eigen::Vector2d> wrapped_coordinates(const haptics::TriangleMesh& mesh) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : mesh.positions) centre += p;
  centre /= std::max<double>(1.0, static_cast<double>(mesh.positions.size()));
  double radius = 0.0;
  for (const Eigen::Vector3d& p : mesh.positions) {
    radius += std::hypot(p.x() - centre.x(), p.z() - centre.z());
  }
  radius /= std::max<double>(1.0, static_cast<double>(mesh.positions.size()));
  constexpr double kTileM = 0.02;
  std::vector<Eigen::Vector2d> uv;
  uv.reserve(mesh.positions.size());
  for (const Eigen::Vector3d& p : mesh.positions) {
    const double angle = std::abs(std::atan2(p.z() - centre.z(), p.x() - centre.x()));
    uv.emplace_back(angle * radius / kTileM, (p.y() - centre.y()) / kTileM);
  }
  return uv;
}

}  // namespace

void set_wet_look(vtkActor* actor) {
  vtkProperty* p = actor->GetProperty();
  p->SetInterpolationToPhong();
  p->SetAmbient(0.08);
  p->SetDiffuse(0.85);
  // A film of peritoneal fluid: a small, bright, white highlight (estimate, by eye against
  // laparoscopic video).
  p->SetSpecular(0.55);
  p->SetSpecularPower(70.0);
  p->SetSpecularColor(1.0, 1.0, 1.0);
}

void OrganActors::add(vtkRenderer* renderer,
                      const std::vector<const haptics::TriangleMesh*>& surfaces,
                      const std::vector<OrganLook>& looks) {
  organs_.clear();
  steps_ = -1;
  for (size_t i = 0; i < surfaces.size() && i < looks.size(); ++i) {
    const haptics::TriangleMesh& mesh = *surfaces[i];
    const OrganLook& look = looks[i];
    Organ o;
    o.db = std::make_unique<haptics::MeshDatabase>(haptics::MeshDatabase::build(mesh));
    o.scratch = std::make_unique<haptics::MeshUpdateScratch>(*o.db);
    o.surface = sim::DeformedSurface(mesh.positions);
    const vtkIdType n = mesh.vertex_count();
    vtkNew<vtkPoints> points;
    points->SetDataTypeToFloat();
    points->SetNumberOfPoints(n);
    o.normals = vtkSmartPointer<vtkFloatArray>::New();
    o.normals->SetNumberOfComponents(3);
    o.normals->SetNumberOfTuples(n);
    o.normals->SetName("Normals");
    for (vtkIdType v = 0; v < n; ++v) {
      const Eigen::Vector3d& p = mesh.positions[static_cast<size_t>(v)];
      points->SetPoint(v, p.x(), p.y(), p.z());
      // The database's normals from the start, so a dent's match their surroundings'.
      const Eigen::Vector3d& nv = o.db->vertex_normal(static_cast<int32_t>(v));
      o.normals->SetTuple3(v, nv.x(), nv.y(), nv.z());
    }
    vtkNew<vtkCellArray> cells;
    cells->AllocateExact(mesh.triangle_count(), 3 * mesh.triangle_count());
    for (const auto& t : mesh.triangles) {
      const vtkIdType ids[3] = {t[0], t[1], t[2]};
      cells->InsertNextCell(3, ids);
    }
    o.poly = vtkSmartPointer<vtkPolyData>::New();
    o.poly->SetPoints(points);
    o.poly->SetPolys(cells);
    o.poly->GetPointData()->SetNormals(o.normals);
    o.textured = look.albedo != nullptr && mesh.uvs.size() == mesh.positions.size() &&
                 look.albedo->width > 0 && look.albedo->height > 0;
    // Without its own texture an organ gets a mottling of its colour on coordinates of its own.
    const std::vector<Eigen::Vector2d> own =
        o.textured ? std::vector<Eigen::Vector2d>{} : wrapped_coordinates(mesh);
    const std::vector<Eigen::Vector2d>& coordinates = o.textured ? mesh.uvs : own;
    {
      vtkNew<vtkFloatArray> uv;
      uv->SetNumberOfComponents(2);
      uv->SetNumberOfTuples(n);
      uv->SetName("TCoords");
      for (vtkIdType v = 0; v < n; ++v) {
        const Eigen::Vector2d& t = coordinates[static_cast<size_t>(v)];
        uv->SetTuple2(v, t.x(), t.y());
      }
      o.poly->GetPointData()->SetTCoords(uv);
    }
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(o.poly);
    mapper->ScalarVisibilityOff();
    o.actor = vtkSmartPointer<vtkActor>::New();
    o.actor->SetMapper(mapper);
    set_wet_look(o.actor);
    // The texture is the colour.
    o.actor->SetTexture(make_texture(o.textured ? *look.albedo : mottled(look.colour)));
    o.actor->GetProperty()->SetColor(1.0, 1.0, 1.0);
    renderer->AddActor(o.actor);
    organs_.push_back(std::move(o));
  }
}

void OrganActors::set_texture_mipmaps(bool on) {
  for (Organ& o : organs_) {
    vtkTexture* t = o.actor->GetTexture();
    if (t == nullptr || (t->GetMipmap() != 0) == on) continue;
    auto fresh = vtkSmartPointer<vtkTexture>::New();
    fresh->SetInputData(t->GetInput());
    fresh->SetInterpolate(t->GetInterpolate());
    fresh->SetRepeat(t->GetRepeat());
    fresh->SetMipmap(on);
    o.actor->SetTexture(fresh);
  }
}

void OrganActors::update(const sim::ModelSnapshot& model) {
  if (model.steps == steps_) return;
  steps_ = model.steps;
  for (size_t i = 0; i < organs_.size() && i < model.organs.size(); ++i) {
    Organ& o = organs_[i];
    if (!o.surface.apply_to(model.organs[i], {.db = o.db.get(), .scratch = o.scratch.get()})) {
      continue;
    }
    // Every vertex whose normal the update recomputed (the moved ones among them), written
    // straight into the float buffers.
    auto* points = static_cast<float*>(o.poly->GetPoints()->GetVoidPointer(0));
    float* normals = o.normals->GetPointer(0);
    for (const int32_t v : o.scratch->dirty_vertices) {
      const Eigen::Vector3d& p = o.db->position(v);
      const Eigen::Vector3d& nv = o.db->vertex_normal(v);
      const auto k = static_cast<size_t>(v) * 3;
      for (int c = 0; c < 3; ++c) {
        points[k + static_cast<size_t>(c)] = static_cast<float>(p[c]);
        normals[k + static_cast<size_t>(c)] = static_cast<float>(nv[c]);
      }
    }
    o.poly->GetPoints()->Modified();
    o.normals->Modified();
  }
}

}  // namespace lap::app
