// The loader's chain reader: [[chains]], a line of capsule links joined by
// ball joints, hung from the world at `anchor` and running along
// `direction`, with an optional [[bodies]] entry hung at its end (a wrecking
// ball). It expands into ordinary bodies and joints, so nothing downstream
// knows chains; what it saves is the arithmetic: link i's joints are at
// anchor + i L d and anchor + (i + 1) L d, its centre half-way between, its
// capsule's axis (local z) along d, and the end body's centre `end_offset`
// beyond the last joint. Changing the link length or the count moves
// everything.
#include "scenes/model/scene_builder.h"
#include "sim/rotation.h"

#include <set>

namespace scenes::loader {
namespace {

struct ChainDef {
    sim::Vec3 anchor = sim::Vec3(0, 2, 0);      // m, the first joint
    sim::Vec3 direction = sim::Vec3(0, -1, 0);  // unit, from the anchor down the chain
    int links = 8;                              // >= 1
    double link_length = 0.2;                   // m, joint to joint
    double radius = 0.03;                       // m, the capsule's; < link_length / 2
    double mass = 1.0;                          // kg, each link
    bool fixed = true;                          // the first link hangs from the world at the anchor
};

ChainDef read_chain(const Section& s) {
    s.only(keys::chain);
    ChainDef c;
    c.anchor = s.vec3("anchor", c.anchor, "m", sim::kMaxBodyReach);
    c.direction = s.direction("direction", c.direction);
    c.links = static_cast<int>(s.integer("links", c.links, 1, 10'000));
    // Sizes and masses within what ODE takes (sim::kMinBodySize .. kMaxBodySize).
    c.link_length = s.positive("link_length", c.link_length, sim::kMaxBodySize, "m");
    c.radius = s.number("radius", c.radius, sim::kMinBodySize, sim::kMaxBodySize, "m");
    // The capsule's straight part, link_length - 2 radius, must be > 0: its
    // round ends meet the neighbours' at the joints.
    if (!(c.link_length - 2.0 * c.radius >= sim::kMinBodySize)) {
        s.fail("link_length", "must be more than twice the radius (" + sim::format_value(2.0 * c.radius) +
                                  " m) by at least " + sim::format_value(sim::kMinBodySize) +
                                  " m: the capsule is [radius, link_length - 2 radius] (got " +
                                  sim::format_value(c.link_length) + ")");
    }
    c.mass = s.number("mass", c.mass, sim::kMinBodyMass, sim::kMaxBodyMass, "kg");
    const sim::Vec3 last = c.anchor + c.links * c.link_length * c.direction;  // m, the last joint
    if (!(last.cwiseAbs().maxCoeff() <= sim::kMaxBodyReach)) {
        s.fail("links", "of " + sim::format_value(c.link_length) + " m from the anchor reach beyond +-" +
                            sim::format_value(sim::kMaxBodyReach) + " m, past what ODE can place");
    }
    c.fixed = s.boolean("fixed", c.fixed);
    return c;
}

// Where the end body's centre of mass goes beyond the last joint, m: end_offset,
// or a plain sphere's radius (its surface then touches the joint).
double end_offset(const Section& s, const sim::BodyDef& end, const std::string& end_name) {
    if (s.node("end_offset") != nullptr) return s.number("end_offset", 0.0, 0.0, sim::kMaxBodySize, "m");
    const bool plain_sphere = end.parts.empty() && end.shape == sim::RigidShape::sphere && end.com.isZero(0.0);
    if (!plain_sphere) {
        s.fail("end", "names " + quote(end_name) +
                          ", not a plain sphere: give end_offset, the distance in m from the last joint to its "
                          "centre of mass");
    }
    return end.size.x();
}

// The [[bodies]] entry `end` names, placed on the chain's line and jointed to
// the last link. Only a [[bodies]] entry (they are the model's first bodies)
// without a position of its own, and each at most once.
void hang_end(SceneBuilder& b, const Section& s, const Section& top, std::set<int>& ends, int last_link,
              const sim::Vec3& last_joint, const sim::Vec3& d) {
    if (s.node("end") == nullptr) {
        if (s.node("end_offset") != nullptr) s.fail("end_offset", "needs end: the body it places");
        return;
    }
    const std::string name = s.string("end", "");
    const auto it = b.body_index.find(name);
    if (it == b.body_index.end()) s.fail("end", "names no body (got " + quote(name) + ")");
    const auto bodies = top.entries("bodies", 10'000);
    const int k = it->second;
    if (k >= static_cast<int>(bodies.size()))
        s.fail("end", "must name a [[bodies]] entry (got " + quote(name) + ", made by a ragdoll or a chain)");
    if (!ends.insert(k).second) s.fail("end", "names " + quote(name) + ", already the end of an earlier chain");
    const Section& entry = bodies[static_cast<std::size_t>(k)];
    if (entry.node("position") != nullptr)
        entry.fail("position", "must not be given: the body is the end of " + s.path() + ", which places it");
    sim::BodyDef& end = b.scene.model.rigid.bodies[static_cast<std::size_t>(k)];
    end.position = last_joint + end_offset(s, end, name) * d;
    sim::RigidJoint j;
    j.joint.type = sim::JointType::ball;
    j.joint.anchor = last_joint;
    j.a = last_link;
    j.b = k;
    b.scene.model.rigid.joints.push_back(j);
    b.joint_nodes.push_back(&s.table());
}

}  // namespace

void read_chains(SceneBuilder& b, const Section& top) {
    sim::RigidModel& m = b.scene.model.rigid;
    std::set<int> ends;  // the [[bodies]] already hung at a chain's end
    const auto chains = top.entries("chains", 1'000);
    for (std::size_t k = 0; k < chains.size(); ++k) {
        const Section& s = chains[k];
        const ChainDef c = read_chain(s);
        const std::string name = s.string("name", "chain" + std::to_string(k) + "_", 64);
        const Color color = s.color("color", palette(k + 3));
        // The capsule's axis is its local z: the shortest turn from z to d.
        const Eigen::Quaterniond along = sim::rotation_from_z(c.direction);
        const sim::Vec3 step = c.link_length * c.direction;  // m, joint to joint
        for (int i = 0; i < c.links; ++i) {
            const std::string link = name + std::to_string(i);
            const int index = static_cast<int>(m.bodies.size());
            if (!b.body_index.emplace(link, index).second)
                s.fail("name", "makes the link " + quote(link) + ", a name already taken");
            sim::BodyDef body;
            body.shape = sim::RigidShape::capsule;
            body.size = sim::Vec3(c.radius, c.link_length - 2.0 * c.radius, 0);
            body.mass = c.mass;
            body.position = c.anchor + (i + 0.5) * step;
            body.orientation = along;
            m.bodies.push_back(body);
            b.scene.body_names.push_back(link);
            b.scene.body_groups.push_back(name);
            b.scene.body_colors.push_back(color);
            // Joint i, at the link's upper end: to the world (the first, when
            // fixed) or to the link before.
            if (i == 0 && !c.fixed) continue;
            sim::RigidJoint j;
            j.joint.type = sim::JointType::ball;
            j.joint.anchor = c.anchor + i * step;
            j.a = i == 0 ? index : index - 1;
            j.b = i == 0 ? -1 : index;
            m.joints.push_back(j);
            b.joint_nodes.push_back(&s.table());
        }
        hang_end(b, s, top, ends, static_cast<int>(m.bodies.size()) - 1, c.anchor + c.links * step, c.direction);
    }
}

}  // namespace scenes::loader
