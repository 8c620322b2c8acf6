#include "terrain_collision.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>

namespace ballast::mujoco {
namespace {

mjfCollision heightFieldCollision[mjNGEOMTYPES];  // MuJoCo's own, for other height fields
constexpr mjtNum kIdentity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

/// Robot geom g against the box the probe holds: MuJoCo's function for the pair, normal from
/// the box to g.
int collideWithBox(const mjModel* m, const mjData* d, mjContact* con, int probe, int g,
                   mjtNum margin) {
  const int type = m->geom_type[g];
  if (type >= mjGEOM_BOX) return mjCOLLISIONFUNC[mjGEOM_BOX][type](m, d, con, probe, g, margin);
  // The table holds each pair once, the lower type first: its normal points from g to the box.
  const int n = mjCOLLISIONFUNC[type][mjGEOM_BOX](m, d, con, g, probe, margin);
  for (int i = 0; i < n; ++i) mju_scl3(con[i].frame, con[i].frame, -1.0);
  return n;
}

int collideTerrain(const mjModel* m, const mjData* d, mjContact* con, int proxy, int g,
                   mjtNum margin) {
  const int field = m->geom_dataid[proxy];
  if (std::strcmp(m->names + m->name_hfieldadr[field], kTerrainIndex) != 0)
    return heightFieldCollision[m->geom_type[g]](m, d, con, proxy, g, margin);
  const mjtNum* extent = m->hfield_size + 4 * field;
  const mjtNum* middle = m->geom_pos + 3 * proxy;  // in the world body: world coordinates
  const int nx = m->hfield_ncol[field], ny = m->hfield_nrow[field];
  const double x0 = middle[0] - extent[0], y0 = middle[1] - extent[1];
  const double resolution = 2 * extent[0] / nx, bottom = middle[2];
  const float* boxOf = m->hfield_data + m->hfield_adr[field];
  const float* boxes = m->hfield_data + m->hfield_adr[field + 1];  // kTerrainBoxes
  const mjtNum* p = d->geom_xpos + 3 * g;
  const double reach = m->geom_rbound[g] + margin;
  if (p[2] - reach > bottom + extent[2]) return 0;  // above the highest top
  // The columns under the geom's bounding sphere.
  auto column = [&](double v, double origin) {
    return static_cast<int>(std::floor((v - origin) / resolution));
  };
  const int ix0 = std::max(0, column(p[0] - reach, x0)),
            ix1 = std::min(nx - 1, column(p[0] + reach, x0));
  const int iy0 = std::max(0, column(p[1] - reach, y0)),
            iy1 = std::min(ny - 1, column(p[1] + reach, y0));
  // The probe: a box geom of the world body, set to each box in turn (axis-aligned). MuJoCo's
  // collision functions read a geom's size from the model and its pose from the data; nothing
  // else reads the probe's, and MuJoCo's own height field collider moves geoms in d likewise.
  const int probe = proxy + 1;
  mjtNum* size = const_cast<mjtNum*>(m->geom_size) + 3 * probe;
  mjtNum* centre = const_cast<mjtNum*>(d->geom_xpos) + 3 * probe;
  mju_copy(const_cast<mjtNum*>(d->geom_xmat) + 9 * probe, kIdentity, 9);
  mjContact found[mjMAXCONPAIR];
  int count = 0;
  for (int iy = iy0; iy <= iy1; ++iy)
    for (int ix = ix0; ix <= ix1; ++ix) {
      const int b = static_cast<int>(boxOf[ix + nx * iy]);
      if (b < 0) continue;
      const float* box = boxes + 5 * b;  // ix0, iy0, ix1, iy1, top
      if (box[4] < p[2] - reach) continue;
      // A box covers a rectangle of columns: collide it once, at its first column here.
      if (ix != std::max(ix0, static_cast<int>(box[0])) ||
          iy != std::max(iy0, static_cast<int>(box[1])))
        continue;
      size[0] = (box[2] - box[0]) * resolution / 2;
      size[1] = (box[3] - box[1]) * resolution / 2;
      size[2] = (box[4] - bottom) / 2;
      centre[0] = x0 + (box[0] + box[2]) * resolution / 2;
      centre[1] = y0 + (box[1] + box[3]) * resolution / 2;
      centre[2] = (bottom + box[4]) / 2;
      const_cast<mjtNum*>(m->geom_rbound)[probe] = mju_norm3(size);
      const int n = collideWithBox(m, d, found, probe, g, margin);
      for (int i = 0; i < n && count < mjMAXCONPAIR; ++i) {
        // Box-box repeats contact points; MuJoCo keeps the last of equal ones, so does this.
        bool repeated = false;
        for (int j = i + 1; j < n && !repeated; ++j)
          repeated = found[i].pos[0] == found[j].pos[0] && found[i].pos[1] == found[j].pos[1] &&
                     found[i].pos[2] == found[j].pos[2];
        if (repeated) continue;
        con[count] = found[i];
        mju_zero3(con[count].frame + 3);  // MuJoCo completes the frame from the normal
        ++count;
      }
    }
  return count;
}

}  // namespace

void installTerrainCollision() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int type = 0; type < mjNGEOMTYPES; ++type) {
      heightFieldCollision[type] = mjCOLLISIONFUNC[mjGEOM_HFIELD][type];
      if (heightFieldCollision[type]) mjCOLLISIONFUNC[mjGEOM_HFIELD][type] = collideTerrain;
    }
  });
}

void writeTerrainIndex(mjModel* m, const plugin::TerrainColumns& c,
                       const std::vector<int>& boxOfColumn) {
  const int field = mj_name2id(m, mjOBJ_HFIELD, kTerrainIndex);
  float* boxOf = m->hfield_data + m->hfield_adr[field];
  float* boxes = m->hfield_data + m->hfield_adr[mj_name2id(m, mjOBJ_HFIELD, kTerrainBoxes)];
  for (int iy = 0; iy < c.ny; ++iy)
    for (int ix = 0; ix < c.nx; ++ix) {
      const int b = boxOfColumn[static_cast<std::size_t>(ix + c.nx * iy)];
      boxOf[ix + c.nx * iy] = static_cast<float>(b);
      if (b < 0) continue;
      float* box = boxes + 5 * b;
      if (box[2] == 0.0f) {  // its first column (terrainBoxes() goes row by row, x fastest)
        box[0] = static_cast<float>(ix), box[1] = static_cast<float>(iy), box[4] = c.top(ix, iy);
      }
      box[2] = std::max(box[2], static_cast<float>(ix + 1));
      box[3] = std::max(box[3], static_cast<float>(iy + 1));
    }
}

}  // namespace ballast::mujoco
