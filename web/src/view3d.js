// The 3D view of one trainee: the tissue mesh from the MeshCache, the tool
// (its +z runs from the tip to the handle, as in the scenes), the force of
// the tissue on the tool as an arrow, and a marker at every puncture or
// cut event. z is up, as in the native viewer. Drag to turn the view around
// the tissue, wheel or pinch to zoom, right-drag or two fingers to pan (a
// mouse, a touch screen or a pen alike: OrbitControls reads pointer events).
import * as THREE from 'three';
import {OrbitControls} from 'three/examples/jsm/controls/OrbitControls.js';

const TISSUE_COLOR = 0xe8a890;
const MARKER_COLORS = {
  puncture: 0x2060ff,
  cut_start: 0x10a040,
  cut_end: 0x10a040
};

export class View3D {
  constructor(canvas) {
    this.canvas = canvas;
    // No multisampling: software GL (a laptop without a GPU driver) draws 4x fewer samples.
    this.renderer = new THREE.WebGLRenderer({canvas, antialias: false, preserveDrawingBuffer: true});
    this.renderer.setClearColor(0xf4f4f4);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(35, 1, 1e-4, 10);
    this.camera.up.set(0, 0, 1);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 2.0));
    const sun = new THREE.DirectionalLight(0xffffff, 1.5);
    sun.position.set(0.3, -0.5, 1);
    this.scene.add(sun);
    this.geometry = new THREE.BufferGeometry();
    // Flat shading: normals from screen-space derivatives, none to recompute
    // on the CPU for every frame of a deforming mesh.
    this.material = new THREE.MeshStandardMaterial(
        {color: TISSUE_COLOR, side: THREE.DoubleSide, roughness: 0.8, flatShading: true});
    this.mesh = new THREE.Mesh(this.geometry, this.material);
    this.mesh.frustumCulled = false;  // its bounds are computed once, when the view is framed
    this.scene.add(this.mesh);
    this.tool =
        new THREE.Mesh(new THREE.CylinderGeometry(1, 1, 1, 12), new THREE.MeshStandardMaterial({color: 0x2050d0}));
    this.tool.visible = false;
    this.scene.add(this.tool);
    this.arrow = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 0.01, 0xff2020);
    this.arrow.visible = false;
    this.scene.add(this.arrow);
    this.markers = new THREE.Group();
    this.scene.add(this.markers);
    this.controls = new OrbitControls(this.camera, canvas);
    // Between frames (a paused trainee) a turn of the view still redraws.
    this.controls.addEventListener('change', () => this.requestRender());
    this.renderPending = false;
    this.positions = null;
    this.extent = 0.05;
    this.tip = null;
    // The canvas's size comes from a ResizeObserver, not read per drawing:
    // reading clientWidth would force a layout, and setting the canvas
    // size, even unchanged, reallocates WebGL's drawing buffer.
    this.size = null;
    this.drawnSize = null;
    new ResizeObserver(([entry]) => {
      const box = entry.contentRect;
      this.size = {width: Math.round(box.width), height: Math.round(box.height)};
    }).observe(canvas);
  }

  // A new trainee or a new keyframe: clear the markers, frame the mesh.
  reset() {
    this.markers.clear();
    this.framed = false;
  }

  // After a frame has been applied to `cache`; tool = Frame.tool.
  update(cache, tool, events) {
    if (!cache.hasMesh) return;
    this.positions = cache.positionsM(this.positions);
    const attribute = this.geometry.getAttribute('position');
    if (!attribute || attribute.array !== this.positions) {
      this.geometry.setAttribute('position', new THREE.BufferAttribute(this.positions, 3));
    } else {
      attribute.needsUpdate = true;
    }
    if (cache.topologyChanged) {
      this.geometry.setIndex(cache.liveTriangles());
      cache.topologyChanged = false;
    }
    if (!this.framed) {
      this.geometry.computeBoundingSphere();
      this.frameMesh();
    }
    this.updateTool(tool);
    for (const e of events || []) this.addMarker(e);
    this.render();
  }

  frameMesh() {
    const sphere = this.geometry.boundingSphere;
    if (!sphere || !isFinite(sphere.radius) || sphere.radius <= 0) return;
    this.extent = sphere.radius;
    const c = sphere.center;
    this.camera.position.set(c.x + 1.6 * sphere.radius, c.y - 2.4 * sphere.radius, c.z + 1.8 * sphere.radius);
    this.camera.near = sphere.radius * 0.01;
    this.camera.far = sphere.radius * 50;
    this.camera.lookAt(c);
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(c);
    this.controls.minDistance = 0.2 * sphere.radius;
    this.controls.maxDistance = 20 * sphere.radius;
    this.controls.update();
    this.framed = true;
  }

  updateTool(tool) {
    if (!tool || tool.tipM.length !== 3 || tool.orientationWxyz.length !== 4) {
      this.tool.visible = this.arrow.visible = false;
      this.tip = null;
      return;
    }
    const [w, x, y, z] = tool.orientationWxyz;
    const up = new THREE.Vector3(0, 0, 1).applyQuaternion(new THREE.Quaternion(x, y, z, w)).normalize();
    const tip = new THREE.Vector3(...tool.tipM);
    const length = 0.8 * this.extent, radius = Math.max(0.012 * this.extent, 2e-4);
    this.tool.position.copy(tip).addScaledVector(up, length / 2);
    this.tool.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), up);
    this.tool.scale.set(radius, length, radius);
    this.tool.visible = true;
    this.tip = tip;
    const f = new THREE.Vector3(...(tool.forceN.length === 3 ? tool.forceN : [0, 0, 0]));
    const magnitude = f.length();
    this.arrow.visible = magnitude > 1e-3;
    if (this.arrow.visible) {
      this.arrow.position.copy(tip);
      this.arrow.setDirection(f.clone().divideScalar(magnitude));
      this.arrow.setLength(Math.min(magnitude * 0.02, this.extent), 0.15 * this.extent, 0.06 * this.extent);
    }
  }

  addMarker(event) {
    const color = MARKER_COLORS[event.kind];
    if (color === undefined || event.whereM.length !== 3) return;
    const dot =
        new THREE.Mesh(new THREE.SphereGeometry(0.03 * this.extent, 12, 8), new THREE.MeshBasicMaterial({color}));
    dot.position.set(...event.whereM);
    this.markers.add(dot);
  }

  resize() {
    const size = this.size;
    if (!size || size.width === 0 || size.height === 0 || size === this.drawnSize) return;
    this.drawnSize = size;
    this.renderer.setSize(size.width, size.height, false);
    this.camera.aspect = size.width / size.height;
    this.camera.updateProjectionMatrix();
  }

  requestRender() {
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => {
      this.renderPending = false;
      this.render();
    });
  }

  render() {
    this.resize();
    this.renderer.render(this.scene, this.camera);
  }

  // Where the tool tip is on the canvas, in CSS pixels (null: no tool): for
  // the browser test, which checks the needle is drawn there.
  projectedTip() {
    return this.tip ? this.project(this.tip) : null;
  }

  // A point of the tool's shaft on the canvas: `fraction` of its length from
  // the tip towards the handle (the part inside the tissue is hidden by it).
  projectedShaft(fraction) {
    if (!this.tip) return null;
    const up = new THREE.Vector3(0, 1, 0).applyQuaternion(this.tool.quaternion);
    return this.project(this.tip.clone().addScaledVector(up, fraction * this.tool.scale.y));
  }

  project(point) {
    const p = point.clone().project(this.camera);
    return {x: ((p.x + 1) / 2) * this.canvas.clientWidth, y: ((1 - p.y) / 2) * this.canvas.clientHeight};
  }
}
