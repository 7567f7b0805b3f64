// The page: reads pyramid.json, sets up three.js (scene, camera, orbit or fly controls) and
// runs the frame loop that updates the quadtree, the tile requests and the status element.
// URL parameters: web/README.md.
'use strict';

(function () {
  var BACKGROUND = 0x101820;

  function parameters() {
    var q = new URLSearchParams(window.location.search);
    var number = function (name, fallback) {
      var v = q.get(name);
      if (v === null || v === '') return fallback;
      var n = Number(v);
      if (!isFinite(n)) throw new Error('URL parameter ' + name + '=' + v + ' is not a number');
      return n;
    };
    var vector = function (name, length) {
      var v = q.get(name);
      if (v === null) return null;
      var parts = v.split(',').map(Number);
      if (parts.length !== length || !parts.every(isFinite)) {
        throw new Error('URL parameter ' + name + '=' + v + ': ' + length + ' numbers expected');
      }
      return parts;
    };
    var light = vector('light', 2) || [315, 45];
    return {
      // A number, or 'auto' (null here): see verticalScale().
      exaggeration: q.get('exaggeration') === 'auto' ? null : number('exaggeration', 1),
      exaggerationGiven: q.has('exaggeration'),
      controls: q.get('controls') === 'fly' ? 'fly' : 'orbit',
      view: q.get('view') || 'oblique',
      splitFactor: number('split', 2),
      maxLevel: q.has('maxlevel') ? number('maxlevel', null) : null,
      light: PyramidMesh.lightDirection(light[0], light[1]),
      camera: vector('camera', 3),
      target: vector('target', 3),
      fov: number('fov', 45),
      pyramid: q.get('pyramid') || '/api/pyramid.json',
    };
  }

  // The vertical exaggeration. Heights are metres (height units); without an extent the root
  // quad is 2^max_level x grid units wide, and a DEM whose heights are not in the units of its
  // grid can stand far taller than wide. 'auto' (and the default, when the heights span more
  // than half the root quad's width) scales the height range to a tenth of that width.
  function verticalScale(info, params) {
    if (info.kind === 'planet' || info.extent) return params.exaggeration === null ? 1 : params.exaggeration;
    var e = info.faces[0].elevation;
    var width = Math.pow(2, e.max_level) * e.grid;
    var range = (e.max_height || 0) - (e.min_height || 0);
    var auto = range > 0 ? 0.1 * width / range : 1;
    if (params.exaggeration === null) return auto;
    if (!params.exaggerationGiven && range > 0.5 * width) return auto;
    return params.exaggeration;
  }

  function mappings(info, params) {
    return info.faces.map(function (face) {
      if (info.kind === 'planet') {
        return new PyramidMesh.FaceMapping(info.radius, face.frame, params.exaggeration);
      }
      // Without an extent the root quad is 2^max_level x grid height units wide: one unit
      // between the samples of the finest level.
      var e = face.elevation, n = Math.pow(2, e.max_level) * e.grid;
      var sx = info.extent ? info.extent.size_x : n, sy = info.extent ? info.extent.size_y : n;
      return new PyramidMesh.PlaneMapping(sx, sy, params.exaggeration);
    });
  }

  // The start view, in the terrain frame (x east, y north, z up): [camera, target].
  function startView(info, maps, params, camera) {
    var f = info.faces[0].elevation;
    var hmid = ((f.min_height || 0) + (f.max_height || 0)) / 2 * params.exaggeration;
    var half = Math.tan(camera.fov * Math.PI / 360);
    var planet = info.kind === 'planet';
    var size = planet ? 2 * info.radius : maps[0].rootSize;
    var target = params.target || (planet ? [0, 0, 0] : [0, 0, hmid]);
    if (params.camera) return [params.camera, target];
    // Far enough for the whole terrain (or planet) to fit in the view.
    var height = ((f.max_height || 0) - (f.min_height || 0)) * params.exaggeration;
    var distance = planet ? 1.3 * info.radius / Math.sin(Math.atan(half))
      : 0.7 * Math.max(size, 2 * height) / half;
    if (params.view === 'top') {
      // Straight down (on a planet: over the north pole), north up on the screen.
      return [[target[0], target[1] - distance * 1e-6, target[2] + distance], target];
    }
    // From the south (on a planet: above 30 N, 20 E), 45 degrees above the horizon.
    if (planet) {
      var lat = 30 * Math.PI / 180, lon = 20 * Math.PI / 180;
      return [[distance * Math.cos(lat) * Math.cos(lon), distance * Math.cos(lat) * Math.sin(lon),
        distance * Math.sin(lat)], target];
    }
    var s = Math.SQRT1_2 * distance;
    return [[target[0], target[1] - s, target[2] + s], target];
  }

  function Viewer(info, params) {
    var self = this;
    this.info = info;
    this.params = params;
    // A logarithmic depth buffer: flying low over a large terrain or planet needs a near plane
    // many orders of magnitude closer than the far one.
    this.renderer = new THREE.WebGLRenderer({ antialias: true, logarithmicDepthBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setSize(window.innerWidth, window.innerHeight);
    this.renderer.setClearColor(BACKGROUND);
    document.body.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    // The terrain frame (z up) in three.js's world (y up): x east stays x, north goes to -z.
    this.group = new THREE.Group();
    this.group.rotation.x = -Math.PI / 2;
    this.scene.add(this.group);
    this.camera = new THREE.PerspectiveCamera(params.fov, window.innerWidth / window.innerHeight, 1, 2);
    params.exaggeration = verticalScale(info, params);
    this.maps = mappings(info, params);
    this.size = info.kind === 'planet' ? 2 * info.radius : this.maps[0].rootSize;
    var view = startView(info, this.maps, params, this.camera);
    this.group.updateMatrixWorld();
    this.camera.position.copy(this.group.localToWorld(new THREE.Vector3().fromArray(view[0])));
    this.target = this.group.localToWorld(new THREE.Vector3().fromArray(view[1]));
    this.camera.lookAt(this.target);
    this.dirty = true;
    this.loader = new PyramidTiles.Loader(PyramidStatus, function () { self.dirty = true; });
    this.terrain = new PyramidQuadtree.Terrain(info, this.maps, this.group, this.loader, {
      splitFactor: params.splitFactor, light: params.light, maxLevel: params.maxLevel,
    });
    this.setControls(params.controls);
    window.addEventListener('resize', function () {
      self.camera.aspect = window.innerWidth / window.innerHeight;
      self.renderer.setSize(window.innerWidth, window.innerHeight);
      self.dirty = true;
    });
    window.addEventListener('keydown', function (event) {
      if (event.key === 'f' || event.key === 'F') self.setControls(self.mode === 'fly' ? 'orbit' : 'fly');
    });
    this.clock = new THREE.Clock();
    this.frame = this.frame.bind(this);
    requestAnimationFrame(this.frame);
  }

  Viewer.prototype.setControls = function (mode) {
    var self = this;
    if (this.controls) this.controls.dispose();
    this.mode = mode;
    if (mode === 'fly') {
      this.controls = new THREE.FlyControls(this.camera, this.renderer.domElement);
      this.controls.movementSpeed = this.size * 0.05;
      this.controls.rollSpeed = 0.4;
      this.controls.dragToLook = true;
    } else {
      // Orbit around the point ahead of the camera, at the distance of the start target.
      var distance = this.camera.position.distanceTo(this.target);
      var ahead = new THREE.Vector3();
      this.camera.getWorldDirection(ahead);
      this.controls = new THREE.OrbitControls(this.camera, this.renderer.domElement);
      this.controls.target.copy(this.camera.position).addScaledVector(ahead, distance);
      this.controls.screenSpacePanning = true;
      this.controls.addEventListener('change', function () { self.dirty = true; });
      this.controls.update();
    }
    this.dirty = true;
  };

  // Near and far planes from the camera's distance to the terrain.
  Viewer.prototype.updateClipping = function () {
    var local = this.group.worldToLocal(this.camera.position.clone());
    var d = Infinity, far = 0;
    this.terrain.roots.forEach(function (root) {
      d = Math.min(d, root.localBox.distanceToPoint(local));
      far = Math.max(far, local.distanceTo(root.localBox.getCenter(new THREE.Vector3())));
    });
    this.camera.near = Math.max(d * 0.5, this.size * 1e-7);
    this.camera.far = far + this.size * 2;
    this.camera.updateProjectionMatrix();
  };

  Viewer.prototype.frame = function () {
    requestAnimationFrame(this.frame);
    var delta = this.clock.getDelta();
    if (this.mode === 'fly') {
      var before = this.camera.matrixWorld.clone();
      this.controls.update(delta);
      this.camera.updateMatrixWorld();
      if (!before.equals(this.camera.matrixWorld)) this.dirty = true;
    }
    this.updateClipping();
    var stable = this.terrain.update(this.camera, this.renderer.domElement.clientWidth || window.innerWidth);
    var waiting = this.loader.pump();
    if (!stable) this.dirty = true;
    if (this.dirty) {
      this.renderer.render(this.scene, this.camera);
      this.dirty = false;
    }
    var idle = stable && waiting === 0 && this.loader.inFlight === 0;
    PyramidStatus.update(idle, this.info.name + ' (' + this.info.kind + ', ' + this.mode +
      ', exaggeration ' + this.params.exaggeration.toPrecision(3) + '): ' +
      this.terrain.drawn + ' quads drawn');
  };

  function start() {
    var params;
    try {
      params = parameters();
    } catch (err) {
      PyramidStatus.error(err.message);
      PyramidStatus.update(true, 'bad URL');
      return;
    }
    fetch(params.pyramid).then(function (response) {
      if (!response.ok) throw new Error('HTTP ' + response.status + ' for ' + params.pyramid);
      return response.json();
    }).then(function (info) {
      if (info.format !== 'libpyramid-serve 1') throw new Error('unknown format ' + info.format);
      window.pyramidViewer = new Viewer(info, params);
    }).catch(function (err) {
      PyramidStatus.error(err.message);
      PyramidStatus.update(true, 'no pyramid');
    });
  }

  start();
})();
