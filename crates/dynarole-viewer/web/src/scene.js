// The 3D scene, drawn from the recording's `drawing` (the robot's own description, the one
// `dynarole show` paints from): every module's rigid parts as their solids in their colours,
// a joint ring where the robot has one, male connectors extended when latched, latches drawn
// between connectors, packets as short arcs. Parts are instanced; nothing here knows a robot.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

const LATCH = 0x1e1e1e;
const DELIVERED = 0x22aa44;
const DROPPED = 0xdd2222;
const Y = new THREE.Vector3(0, 1, 0);
const Z = new THREE.Vector3(0, 0, 1);

export class Scene {
  constructor(container, recording) {
    this.rec = recording;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    container.appendChild(this.renderer.domElement);
    this.container = container;
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xf4f4f4);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x888888, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(5, 10, 7);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.05, 2000);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.buildModules();
    this.latchGroup = new THREE.Group();
    this.packetGroup = new THREE.Group();
    this.scene.add(this.latchGroup, this.packetGroup);
    this.resize();
    this.resetCamera(recording.keyframes[0].poses);
  }

  // One instanced mesh per part of a module (each the solid the drawing gives it), the joint
  // rings, male and female connectors: a handful of draw calls whatever the robot's size.
  buildModules() {
    const rec = this.rec;
    const n = rec.modules.length;
    const many = n > 200;
    const segments = many ? 10 : 28;
    const drawing = rec.drawing;
    const solid = (s) =>
      s.kind === 'dome'
        ? new THREE.SphereGeometry(s.radius, segments, segments / 2, 0, Math.PI * 2, 0, Math.PI / 2)
        : new THREE.BoxGeometry(s.edge, s.edge, s.edge);
    const prong = new THREE.CylinderGeometry(0.05, 0.05, 1, 8);
    prong.translate(0, 0.5, 0);
    const socket = new THREE.CylinderGeometry(0.07, 0.07, 0.02, 10);
    const instanced = (geometry, colour, count) => {
      const mesh = new THREE.InstancedMesh(geometry, new THREE.MeshStandardMaterial({ color: colour, roughness: 0.6 }), count);
      // Instances move every frame; their bounds are not worth recomputing for culling.
      mesh.frustumCulled = false;
      this.scene.add(mesh);
      return mesh;
    };
    // Parts take their colour per instance (white material), so that a module can flash.
    this.parts = drawing.parts.map((part) => instanced(solid(part.solid), 0xffffff, n));
    // A hex colour is read as sRGB, as the colours of `dynarole show` are.
    const hex = ([r, g, b]) => (r << 16) | (g << 8) | b;
    this.partColours = drawing.parts.map((part) => new THREE.Color(hex(part.colour)));
    this.flashColour = new THREE.Color(0xff3030);
    const ring = drawing.joint_ring;
    this.joints = ring ? instanced(new THREE.TorusGeometry(ring.radius, ring.tube, 6, segments), 0x222222, n) : null;
    const perModule = many ? [] : rec.connectors.map((c, k) => k);
    const males = perModule.filter((k) => rec.connectors[k].male);
    const females = perModule.filter((k) => !rec.connectors[k].male);
    this.connectorParts = [
      { kinds: males, mesh: instanced(prong, 0x666666, Math.max(1, n * males.length)) },
      { kinds: females, mesh: instanced(socket, 0x222222, Math.max(1, n * females.length)) },
    ];
    this.connectorParts.forEach((part) => (part.mesh.count = n * part.kinds.length));
    this.centres = rec.modules.map(() => new THREE.Vector3());
  }

  resize() {
    const w = this.container.clientWidth || 800;
    const h = this.container.clientHeight || 600;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  resetCamera(poses) {
    const box = new THREE.Box3();
    for (const p of poses) box.expandByPoint(new THREE.Vector3(...p.centre));
    const centre = box.getCenter(new THREE.Vector3());
    const size = Math.max(4, box.getSize(new THREE.Vector3()).length());
    this.camera.position.copy(centre).add(new THREE.Vector3(0.9, 0.8, 1.2).multiplyScalar(size));
    this.controls.target.copy(centre);
    this.controls.update();
  }

  // Places every part at the poses of `state` (from World.at).
  show(state, flashing, latchedMales) {
    const v = new THREE.Vector3();
    const part = new THREE.Object3D();
    const place = (mesh, index) => {
      part.updateMatrix();
      mesh.setMatrixAt(index, part.matrix);
    };
    this.centres.forEach((centre, i) => {
      const pose = state.poses[i];
      centre.set(...pose.centre);
      this.parts.forEach((mesh, h) => {
        const placed = pose.parts[h];
        part.position.set(...placed.centre);
        part.quaternion.setFromUnitVectors(Y, v.set(...placed.up).normalize());
        part.scale.setScalar(1);
        place(mesh, i);
        mesh.setColorAt(i, flashing.has(i) ? this.flashColour : this.partColours[h]);
      });
      if (this.joints) {
        part.position.copy(centre);
        part.quaternion.setFromUnitVectors(Z, v.set(...pose.parts[0].up).normalize());
        part.scale.setScalar(1);
        place(this.joints, i);
      }
      for (const { kinds, mesh } of this.connectorParts) {
        kinds.forEach((k, j) => {
          this.placeConnector(part, pose, k, latchedMales.has(i * 64 + k));
          place(mesh, i * kinds.length + j);
        });
      }
    });
    const meshes = [...this.parts, ...this.connectorParts.map((p) => p.mesh)];
    if (this.joints) meshes.push(this.joints);
    for (const mesh of meshes) {
      mesh.instanceMatrix.needsUpdate = true;
      if (mesh.instanceColor) mesh.instanceColor.needsUpdate = true;
    }
    this.showLatches(state);
  }

  // Sets `part` (position, direction, length) to connector k of `pose`.
  placeConnector(part, pose, k, extended) {
    const info = this.rec.connectors[k];
    const at = new THREE.Vector3(...pose.connectors[k]);
    const from = new THREE.Vector3(...pose.parts[info.part].centre);
    const out = at.clone().sub(from).normalize();
    part.quaternion.setFromUnitVectors(Y, out);
    if (info.male) {
      // Retracted: the hooks stay inside the shell; extended: they reach the neighbour.
      const length = extended ? 0.3 : 0.08;
      part.position.copy(at).addScaledVector(out, -0.2);
      part.scale.set(1, length + 0.2, 1);
    } else {
      part.position.copy(at).addScaledVector(out, -0.23);
      part.scale.setScalar(1);
    }
  }

  showLatches(state) {
    this.latchGroup.clear();
    const material = new THREE.LineBasicMaterial({ color: LATCH });
    const points = [];
    for (const [a, ca, b, cb] of state.latches) {
      points.push(new THREE.Vector3(...state.poses[a].connectors[ca]), new THREE.Vector3(...state.poses[b].connectors[cb]));
    }
    if (points.length) {
      const geometry = new THREE.BufferGeometry().setFromPoints(points);
      this.latchGroup.add(new THREE.LineSegments(geometry, material));
    }
  }

  showPackets(state, packets) {
    this.packetGroup.clear();
    for (const p of packets) {
      const a = new THREE.Vector3(...state.poses[p.from[0]].connectors[p.from[1]]);
      const b = new THREE.Vector3(...state.poses[p.to[0]].connectors[p.to[1]]);
      const mid = a.clone().add(b).multiplyScalar(0.5);
      const lift = new THREE.Vector3(...state.poses[p.from[0]].centre).sub(a).normalize().multiplyScalar(-0.3);
      const curve = new THREE.QuadraticBezierCurve3(a, mid.add(lift).add(new THREE.Vector3(0, 0.25, 0)), b);
      const geometry = new THREE.BufferGeometry().setFromPoints(curve.getPoints(8));
      const colour = p.fate === 'delivered' ? DELIVERED : DROPPED;
      this.packetGroup.add(new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: colour })));
    }
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  // Screen position (CSS pixels) of module i's centre, for labels.
  screen(i) {
    const v = this.centres[i].clone().project(this.camera);
    const w = this.container.clientWidth;
    const h = this.container.clientHeight;
    return { x: ((v.x + 1) / 2) * w, y: ((1 - v.y) / 2) * h, visible: v.z < 1 };
  }

  // The module under a mouse position, if any.
  pick(x, y) {
    const ray = new THREE.Raycaster();
    const w = this.container.clientWidth;
    const h = this.container.clientHeight;
    ray.setFromCamera(new THREE.Vector2((x / w) * 2 - 1, 1 - (y / h) * 2), this.camera);
    const hit = ray.intersectObjects(this.parts, false)[0];
    return hit ? hit.instanceId : null;
  }
}
