// ohrp view's page: the scene built from the server's description (view.js calls buildScene
// with the hello's `scene`): its meshes and height fields as three.js geometries, each geom as
// a three.js object (MuJoCo sizes), the static ones placed once, the moving ones (the robot's,
// in the server's order) kept in `moving` for showPoses.

let meshes = [];  // the description's meshes as three.js geometries, shared by their geoms

// base64 to the bytes it encodes
function bytesOf(b64) {
  const s = atob(b64), out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
  return out.buffer;
}

// one of the description's meshes (vertices and triangles in the frame its geoms' poses place;
// little-endian float32 and uint32 arrays in base64)
function makeMesh(m) {
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(bytesOf(m.vertices)), 3));
  geo.setIndex(new THREE.BufferAttribute(new Uint32Array(bytesOf(m.faces)), 1));
  geo.computeVertexNormals();
  return geo;
}

let hfields = [];  // the description's height fields as three.js geometries

// one of the description's height fields: a grid of triangles over the samples, row r at
// y = -sy + 2 sy r / (nrow - 1), column c at x = -sx + 2 sx c / (ncol - 1) in its geom's frame,
// at the elevations [m] of the float32 array (row-major, base64)
function makeHfield(h) {
  const z = new Float32Array(bytesOf(h.heights)), nr = h.nrow, nc = h.ncol;
  const sx = h.size[0], sy = h.size[1];
  const pos = new Float32Array(3 * nr * nc);
  for (let r = 0; r < nr; ++r) {
    for (let c = 0; c < nc; ++c) {
      const k = r * nc + c;
      pos[3 * k] = -sx + 2 * sx * c / (nc - 1);
      pos[3 * k + 1] = -sy + 2 * sy * r / (nr - 1);
      pos[3 * k + 2] = z[k];
    }
  }
  const idx = new Uint32Array(6 * (nr - 1) * (nc - 1));
  let i = 0;
  for (let r = 0; r + 1 < nr; ++r) {
    for (let c = 0; c + 1 < nc; ++c) {
      const a = r * nc + c, b = a + 1, d = a + nc, e = d + 1;
      idx.set([a, b, e, a, e, d], i);  // counter-clockwise seen from above
      i += 6;
    }
  }
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  geo.setIndex(new THREE.BufferAttribute(idx, 1));
  geo.computeVertexNormals();
  return geo;
}

// one geom as a three.js object (MuJoCo sizes are half-lengths and radii)
function makeGeom(g) {
  const s = g.size, color = new THREE.Color(g.rgba[0], g.rgba[1], g.rgba[2]);
  const mat = new THREE.MeshLambertMaterial({color, transparent: g.rgba[3] < 1, opacity: g.rgba[3]});
  let obj;
  if (g.type === 'box') {
    obj = new THREE.Mesh(new THREE.BoxBufferGeometry(2 * s[0], 2 * s[1], 2 * s[2]), mat);
  } else if (g.type === 'sphere' || g.type === 'ellipsoid') {
    obj = new THREE.Mesh(new THREE.SphereBufferGeometry(1, 20, 14), mat);
    obj.scale.set(s[0], g.type === 'sphere' ? s[0] : s[1], g.type === 'sphere' ? s[0] : s[2]);
  } else if (g.type === 'cylinder' || g.type === 'capsule') {
    const cyl = new THREE.CylinderBufferGeometry(s[0], s[0], 2 * s[1], 20);
    cyl.rotateX(Math.PI / 2);  // three's cylinders run along y, MuJoCo's along z
    obj = new THREE.Group();
    obj.add(new THREE.Mesh(cyl, mat));
    if (g.type === 'capsule') {
      for (const z of [-s[1], s[1]]) {
        const cap = new THREE.Mesh(new THREE.SphereBufferGeometry(s[0], 16, 10), mat);
        cap.position.z = z;
        obj.add(cap);
      }
    }
  } else if (g.type === 'mesh') {
    if (meshes[g.mesh]) obj = new THREE.Mesh(meshes[g.mesh], mat);
  } else if (g.type === 'hfield') {
    if (hfields[g.hfield]) obj = new THREE.Mesh(hfields[g.hfield], mat);
  } else if (g.type === 'plane') {
    const w = s[0] > 0 ? 2 * s[0] : 40, h = s[1] > 0 ? 2 * s[1] : 40;
    // a checker of 0.5 m squares (as in the paper's video): walking progress shows while the
    // camera follows the robot (thin grid lines mostly vanish in software rendering)
    const floor = new THREE.MeshLambertMaterial({map: checkerTexture(w / 0.5, h / 0.5)});
    obj = new THREE.Group();
    obj.add(new THREE.Mesh(new THREE.PlaneBufferGeometry(w, h), floor));
  }
  return obj;
}

// a texture of 2 x 2 squares (dark, light) repeated `nx` x `ny` times over a plane
function checkerTexture(nx, ny) {
  const c = document.createElement('canvas');
  c.width = c.height = 2;
  const g = c.getContext('2d');
  g.fillStyle = '#3c4650'; g.fillRect(0, 0, 2, 2);
  g.fillStyle = '#6a7886'; g.fillRect(0, 0, 1, 1); g.fillRect(1, 1, 1, 1);
  const t = new THREE.CanvasTexture(c);
  t.magFilter = THREE.NearestFilter;  // sharp edges near, mipmapped (grey) far
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.repeat.set(nx / 2, ny / 2);
  return t;
}

function setPose(obj, p) {
  obj.position.set(p[0], p[1], p[2]);
  obj.quaternion.set(p[4], p[5], p[6], p[3]);  // three: (x, y, z, w)
}

function buildScene(desc) {
  meshes = (desc.meshes || []).map(makeMesh);
  hfields = (desc.hfields || []).map((h) => (h.nrow > 1 && h.ncol > 1 ? makeHfield(h) : null));
  for (const g of desc.static) {
    const o = makeGeom(g);
    if (o) { setPose(o, g.pose); scene3.add(o); }
  }
  moving = desc.moving.map((g) => {
    const o = makeGeom(g);
    if (o) { o.userData.body = g.body; scene3.add(o); }  // the body: control.js picks it by a click
    return o;
  });
}
