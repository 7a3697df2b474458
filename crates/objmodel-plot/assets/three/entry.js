// The parts of three.js that the 3D view (src/view_page.html) uses, bundled by update.sh into
// three.bundle.min.js: one classic script that defines the global THREE (an inline ES module
// could not import another inline module on a file:// page). Add a name here when the page
// needs one more, then run update.sh.
export {
  AmbientLight, ArrowHelper, AxesHelper, Box3, BufferGeometry, Color, DirectionalLight,
  DoubleSide, Float32BufferAttribute, GridHelper, Group, Line, LineBasicMaterial,
  LineDashedMaterial, LineSegments, Mesh, MeshBasicMaterial, MeshLambertMaterial,
  PerspectiveCamera, Quaternion, Raycaster, Scene, Sphere, SphereGeometry, Vector2, Vector3,
  WebGLRenderer,
} from 'three';
export { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
