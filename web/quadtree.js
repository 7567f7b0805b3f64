// The terrain quadtree and its level of detail, as the seeds' terrain node does it: a quad is
// subdivided when the camera is closer to it than k times its size (k: the split distance
// factor), down to the elevation pyramid's max_level (or the ortho's, if deeper). Distances are max(|dx|, |dy|, |dz|) to the
// quad's box on a plane, the Euclidean distance to it on a planet. Quads outside the view
// frustum are not subdivided and their tiles not requested. A quad is drawn until its four
// children have their tiles (a child whose elevation tile is absent keeps its parent drawn).
'use strict';

var PyramidQuadtree = (function () {
  var MAX_BUILDS_PER_FRAME = 4;

  // face: an entry of pyramid.json's faces; mapping: PyramidMesh's mapping of that face.
  function Node(face, mapping, level, tx, ty, hmin, hmax) {
    this.face = face;
    this.mapping = mapping;
    this.level = level;
    this.tx = tx;
    this.ty = ty;
    this.children = null;
    this.mesh = null;
    this.elevation = null; // the loader's entries
    this.ortho = null;
    this.setHeights(hmin, hmax);
  }

  // The box of the quad in the terrain frame, from points of the quad at its lowest and
  // highest heights (5 x 5 of them on a planet, where a quad bulges).
  Node.prototype.setHeights = function (hmin, hmax) {
    this.hmin = hmin;
    this.hmax = hmax;
    var span = 1 / Math.pow(2, this.level), x0 = this.tx * span, y0 = this.ty * span;
    var steps = this.mapping instanceof PyramidMesh.PlaneMapping ? 1 : 4;
    var box = new THREE.Box3(), p = [0, 0, 0], v = new THREE.Vector3();
    this.directions = steps > 1 ? [] : null; // unit vectors of the planet's points, for the horizon
    for (var j = 0; j <= steps; ++j) {
      for (var i = 0; i <= steps; ++i) {
        for (var s = 0; s < 2; ++s) {
          this.mapping.point(x0 + span * i / steps, y0 + span * j / steps, s ? hmax : hmin, p);
          box.expandByPoint(v.set(p[0], p[1], p[2]));
        }
        if (this.directions) this.directions.push(v.clone().normalize());
      }
    }
    this.localBox = box;
    this.worldBox = null;
  };

  Node.prototype.size = function () {
    return this.mapping.rootSize / Math.pow(2, this.level);
  };

  function Terrain(info, mappings, group, loader, options) {
    this.info = info;
    this.group = group;
    this.loader = loader;
    this.options = options; // {splitFactor, light, maxLevel}
    this.roots = info.faces.map(function (face, index) {
      var e = face.elevation;
      return new Node(face, mappings[index], 0, 0, 0,
        e.min_height === null || e.min_height === undefined ? 0 : e.min_height,
        e.max_height === null || e.max_height === undefined ? 0 : e.max_height);
    });
    this.frustum = new THREE.Frustum();
    this.matrix = new THREE.Matrix4();
    this.cameraLocal = new THREE.Vector3();
    this.changed = false;
    this.builds = 0;
    this.drawn = 0;
  }

  // The elevation pyramid's deepest level, or the ortho's where it is deeper: quads below the
  // elevation's take their heights from their ancestor's tile (never requested beyond it).
  Terrain.prototype.maxLevel = function (node) {
    var max = node.face.elevation.max_level;
    if (node.face.ortho) max = Math.max(max, node.face.ortho.max_level);
    return this.options.maxLevel === null ? max : Math.min(max, this.options.maxLevel);
  };

  // One frame: visits the quadtree from the camera. Returns true when nothing changed.
  Terrain.prototype.update = function (camera, viewportWidth) {
    camera.updateMatrixWorld();
    this.group.updateMatrixWorld();
    this.matrix.multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse);
    this.frustum.setFromMatrix(this.matrix);
    this.cameraLocal.copy(camera.position);
    this.group.worldToLocal(this.cameraLocal);
    // The seeds' split distance: k for a 1024-pixel-wide viewport with an 80-degree field of
    // view, scaled so that quads keep about the same size in pixels.
    var fov = camera.fov * Math.PI / 180;
    this.split = this.options.splitFactor * (viewportWidth / 1024) *
      Math.tan(40 * Math.PI / 180) / Math.tan(fov / 2);
    this.changed = false;
    this.builds = 0;
    this.drawn = 0;
    for (var i = 0; i < this.roots.length; ++i) this.visit(this.roots[i]);
    return !this.changed;
  };

  Terrain.prototype.distance = function (node) {
    var b = node.localBox, c = this.cameraLocal;
    var dx = Math.max(b.min.x - c.x, 0, c.x - b.max.x);
    var dy = Math.max(b.min.y - c.y, 0, c.y - b.max.y);
    var dz = Math.max(b.min.z - c.z, 0, c.z - b.max.z);
    if (node.mapping instanceof PyramidMesh.PlaneMapping) return Math.max(dx, dy, dz);
    return Math.sqrt(dx * dx + dy * dy + dz * dz);
  };

  Terrain.prototype.isVisible = function (node) {
    if (!node.worldBox) node.worldBox = node.localBox.clone().applyMatrix4(this.group.matrixWorld);
    return this.frustum.intersectsBox(node.worldBox) && !this.beyondHorizon(node);
  };

  // On a planet, whether all the quad's points (at its highest height) lie behind the horizon of
  // the sphere of its lowest heights: a point at radius rp, seen from the distance d, is hidden
  // by a sphere of radius r0 beyond the angle acos(r0 / d) + acos(r0 / rp) from the camera.
  Terrain.prototype.beyondHorizon = function (node) {
    if (!node.directions) return false;
    var m = node.mapping, c = this.cameraLocal, d = c.length();
    var lowest = this.roots.reduce(function (low, root) { return Math.min(low, root.hmin); }, 0);
    var r0 = m.radius + lowest * m.exaggeration;
    var rp = m.radius + node.hmax * m.exaggeration;
    if (d <= r0 || rp <= r0) return false;
    var limit = Math.acos(r0 / d) + Math.acos(r0 / rp);
    if (limit >= Math.PI) return false;
    var cosLimit = Math.cos(limit);
    for (var i = 0; i < node.directions.length; ++i) {
      if (node.directions[i].dot(c) / d > cosLimit) return false;
    }
    return true;
  };

  // Asks for the node's tiles; true once it can be drawn (elevation and ortho answered).
  Terrain.prototype.request = function (node, priority) {
    var face = node.face, tiles = this.info.tiles;
    var ed = Math.max(0, node.level - face.elevation.max_level), el = node.level - ed;
    var etx = node.tx >> ed, ety = node.ty >> ed; // the elevation tile holding the quad
    node.elevation = this.loader.want(face.face + '/e/' + el + '/' + etx + '/' + ety,
      PyramidTiles.expand(tiles.elevation, face.face, el, etx, ety), 'elevation', priority);
    node.elevationPlace = { d: ed, ox: (node.tx - (etx << ed)) / (1 << ed), oy: (node.ty - (ety << ed)) / (1 << ed) };
    if (face.ortho) {
      var d = Math.max(0, node.level - face.ortho.max_level), level = node.level - d;
      var otx = node.tx >> d, oty = node.ty >> d; // the ortho tile holding the quad
      node.ortho = this.loader.want(face.face + '/o/' + level + '/' + otx + '/' + oty,
        PyramidTiles.expand(tiles.ortho, face.face, level, otx, oty), 'ortho', priority + 0.5);
      node.orthoPlace = { d: d, ox: (node.tx - (otx << d)) / (1 << d), oy: (node.ty - (oty << d)) / (1 << d) };
    }
    var answered = function (entry) {
      return !entry || entry.state === 'loaded' || entry.state === 'absent' || entry.state === 'failed';
    };
    return answered(node.elevation) && answered(node.ortho);
  };

  // True when the node has its mesh (built now if its tiles are in and the budget allows).
  Terrain.prototype.ensureMesh = function (node, priority) {
    if (node.mesh) return true;
    if (!this.request(node, priority)) return false;
    if (node.elevation.state !== 'loaded') return false;
    if (this.builds >= MAX_BUILDS_PER_FRAME) { this.changed = true; return false; }
    this.builds += 1;
    this.changed = true;
    var e = node.face.elevation, o = node.face.ortho, data = node.elevation.data;
    var ortho = null;
    if (node.ortho && node.ortho.state === 'loaded') {
      ortho = {
        texture: node.ortho.data.texture, side: node.ortho.data.side, border: o.border,
        tileSize: o.tile_size, ox: node.orthoPlace.ox, oy: node.orthoPlace.oy,
        scale: 1 / (1 << node.orthoPlace.d),
      };
    }
    var built = PyramidMesh.build(node.mapping, {
      level: node.level, tx: node.tx, ty: node.ty, heights: data.heights, side: data.side,
      border: e.border, grid: e.grid, depth: node.elevationPlace.d, ox: node.elevationPlace.ox,
      oy: node.elevationPlace.oy,
    }, ortho, this.options.light);
    node.mesh = built.mesh;
    node.mesh.visible = false;
    node.setHeights(built.hmin, built.hmax);
    this.group.add(node.mesh);
    return true;
  };

  Terrain.prototype.show = function (node, shown) {
    if (node.mesh && node.mesh.visible !== shown) {
      node.mesh.visible = shown;
      this.changed = true;
    }
    if (shown) this.drawn += 1;
  };

  Terrain.prototype.collapse = function (node) {
    if (!node.children) return;
    for (var i = 0; i < 4; ++i) {
      var child = node.children[i];
      this.collapse(child);
      if (child.mesh) {
        this.group.remove(child.mesh);
        PyramidMesh.dispose(child.mesh);
      }
    }
    node.children = null;
    this.changed = true;
  };

  Terrain.prototype.visit = function (node) {
    var visible = this.isVisible(node);
    var distance = this.distance(node), size = node.size();
    var priority = node.level * 1000 + Math.min(999, distance / size);
    if (!visible && node.level > 0) {
      this.collapse(node);
      this.show(node, false);
      return;
    }
    if (!this.ensureMesh(node, priority)) {
      this.show(node, false);
      return;
    }
    var split = visible && node.level < this.maxLevel(node) && distance < this.split * size;
    if (!split) {
      this.collapse(node);
      this.show(node, true);
      return;
    }
    if (!node.children) {
      node.children = [];
      for (var i = 0; i < 4; ++i) {
        node.children.push(new Node(node.face, node.mapping, node.level + 1,
          2 * node.tx + (i & 1), 2 * node.ty + (i >> 1), node.hmin, node.hmax));
      }
      this.changed = true;
    }
    // The children replace the node once every visible one has its mesh.
    var ready = true;
    for (var c = 0; c < 4; ++c) {
      var child = node.children[c];
      if (!this.isVisible(child)) continue;
      var childPriority = child.level * 1000 + Math.min(999, this.distance(child) / child.size());
      // Not ready while loading, and for good when its elevation tile is absent (404).
      if (!this.ensureMesh(child, childPriority)) ready = false;
    }
    if (!ready) {
      for (var h = 0; h < 4; ++h) {
        this.collapse(node.children[h]);
        this.show(node.children[h], false);
      }
      this.show(node, true);
      return;
    }
    this.show(node, false);
    for (var v = 0; v < 4; ++v) this.visit(node.children[v]);
  };

  return { Terrain: Terrain };
})();
