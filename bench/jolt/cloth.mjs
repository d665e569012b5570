// The Jolt peer of sb_bench_pbd (bench/bench_pbd.c): Jolt Physics' soft
// body in its WebAssembly build (npm package jolt-physics, single-threaded
// wasm), on Node.js.
//
//   node bench/jolt/cloth.mjs [--steps 400] [--repeats 5] [--iterations 5]
//
// The same sheet as softbond's: 1 m × 1 m, 100 × 100 vertices, 1e-5 kg each
// (0.1 kg/m²), hanging from the two corners of one edge, gravity 9.81 m/s²,
// dt 1 ms, 5 iterations, no damping, no sleeping. Jolt's CreateConstraints
// makes its edge constraints from the faces (stretch: 19 800 grid edges
// and 9 801 diagonals; shear: the 9 801 other diagonals; no bend), each with
// compliance 1/k = 0.01 m/N (softbond's k = 100 N/m). Each repeat times
// --steps steps of PhysicsSystem::Update through JoltInterface.Step after as
// many to warm up, from a fresh body; the best time counts. Prints
//   jolt,bonds,1,STEPS,MS_PER_STEP,EDGE_PROJECTIONS,0
// (edge projections per step: edge constraints × iterations).
import initJolt from "jolt-physics/wasm";

const options = { steps: 400, repeats: 5, iterations: 5 };
for (let a = 2; a < process.argv.length; a += 2) {
    const key = process.argv[a].replace(/^--/, "");
    if (!(key in options) || !(Number(process.argv[a + 1]) > 0)) {
        console.error("usage: node cloth.mjs [--steps N] [--repeats N] [--iterations N]");
        process.exit(2);
    }
    options[key] = Number(process.argv[a + 1]);
}

const SIZE = 100, WIDTH = 1.0, MASS = 1e-5, COMPLIANCE = 1 / 100, DT = 1e-3;
const Jolt = await initJolt();

function makeSystem() {
    const settings = new Jolt.JoltSettings();
    const objectFilter = new Jolt.ObjectLayerPairFilterTable(2);
    objectFilter.EnableCollision(0, 1);
    objectFilter.EnableCollision(1, 1);
    const layers = new Jolt.BroadPhaseLayerInterfaceTable(2, 2);
    layers.MapObjectToBroadPhaseLayer(0, new Jolt.BroadPhaseLayer(0));
    layers.MapObjectToBroadPhaseLayer(1, new Jolt.BroadPhaseLayer(1));
    settings.mObjectLayerPairFilter = objectFilter;
    settings.mBroadPhaseLayerInterface = layers;
    settings.mObjectVsBroadPhaseLayerFilter = new Jolt.ObjectVsBroadPhaseLayerFilterTable(layers, 2, objectFilter, 2);
    const jolt = new Jolt.JoltInterface(settings);
    Jolt.destroy(settings);
    jolt.GetPhysicsSystem().SetGravity(new Jolt.Vec3(0, -9.81, 0));
    return jolt;
}

// The grid in the xz plane (gravity along −y), two triangles a cell, the
// corners (0, SIZE−1) and (SIZE−1, SIZE−1) pinned (inverse mass 0).
function makeCloth() {
    const shared = new Jolt.SoftBodySharedSettings();
    const vertex = new Jolt.SoftBodySharedSettingsVertex();
    const h = WIDTH / (SIZE - 1), index = (x, z) => x + z * SIZE;
    for (let z = 0; z < SIZE; ++z)
        for (let x = 0; x < SIZE; ++x) {
            vertex.mPosition.x = h * x;
            vertex.mPosition.y = 0;
            vertex.mPosition.z = h * z;
            vertex.mInvMass = z === SIZE - 1 && (x === 0 || x === SIZE - 1) ? 0 : 1 / MASS;
            shared.mVertices.push_back(vertex);
        }
    Jolt.destroy(vertex);
    const face = new Jolt.SoftBodySharedSettingsFace(0, 0, 0, 0);
    for (let z = 0; z < SIZE - 1; ++z)
        for (let x = 0; x < SIZE - 1; ++x) {
            face.set_mVertex(0, index(x, z));
            face.set_mVertex(1, index(x, z + 1));
            face.set_mVertex(2, index(x + 1, z + 1));
            shared.AddFace(face);
            face.set_mVertex(1, index(x + 1, z + 1));
            face.set_mVertex(2, index(x + 1, z));
            shared.AddFace(face);
        }
    Jolt.destroy(face);
    const attributes = new Jolt.SoftBodySharedSettingsVertexAttributes();
    attributes.mCompliance = COMPLIANCE;
    attributes.mShearCompliance = COMPLIANCE;
    shared.CreateConstraints(attributes, 1, Jolt.SoftBodySharedSettings_EBendType_None);
    Jolt.destroy(attributes);
    shared.Optimize();
    return shared;
}

// Seconds for options.steps steps of a fresh cloth, after as many to warm up.
function timeSteps(jolt, shared) {
    const creation = new Jolt.SoftBodyCreationSettings(shared, new Jolt.RVec3(0, 0, 0), new Jolt.Quat(0, 0, 0, 1), 1);
    creation.mNumIterations = options.iterations;
    creation.mLinearDamping = 0;
    creation.mAllowSleeping = false;
    const bodies = jolt.GetPhysicsSystem().GetBodyInterface();
    const body = bodies.CreateSoftBody(creation);
    Jolt.destroy(creation);
    bodies.AddBody(body.GetID(), Jolt.EActivation_Activate);
    let start = 0n;
    for (let k = 0; k < 2 * options.steps; ++k) {
        if (k === options.steps) start = process.hrtime.bigint();
        jolt.Step(DT, 1);
    }
    const seconds = Number(process.hrtime.bigint() - start) * 1e-9;
    bodies.RemoveBody(body.GetID());
    bodies.DestroyBody(body.GetID());
    return seconds;
}

const jolt = makeSystem();
const shared = makeCloth();
shared.AddRef(); /* kept for every repeat's body: the last body to let go of it would free it */
const edges = shared.mEdgeConstraints.size();
let best = Infinity;
for (let r = 0; r < options.repeats; ++r) best = Math.min(best, timeSteps(jolt, shared));
console.log(`jolt,bonds,1,${options.steps},${((1e3 * best) / options.steps).toFixed(6)},${edges * options.iterations},0`);
