// The library's types as the build compiled them (core/lang/compiled_types.h) are the types its
// text parses to: the CLI reads the compiled ones, this test process parses the text.

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/lang/builtin_library.h"
#include "core/lang/compiled_types.h"
#include "core/lang/type_serial.h"

namespace momenta {
namespace {

TEST(CompiledTypesTest, TheLibraryIsCompiledAsItsTextParses) {
  // Byte for byte: every record, connector type, component type and function, every field, every
  // expression node and every location (file:line:col).
  const SerializedLibrary parsed = SerializeLibrary();
  const CompiledLibraryTypes compiled = CompiledBuiltinTypes();
  ASSERT_EQ(parsed.offsets.size(), compiled.entries + 1);
  EXPECT_TRUE(std::equal(parsed.offsets.begin(), parsed.offsets.end(), compiled.offsets));
  ASSERT_EQ(parsed.bytes.size(), compiled.offsets[compiled.entries]);
  EXPECT_TRUE(parsed.bytes == std::string_view(compiled.bytes, parsed.bytes.size()));
  // Each component type is one entry's bytes.
  size_t types = 0;
  for (size_t k = 0; k < parsed.kinds.size(); ++k) {
    if (parsed.kinds[k] != 't') continue;
    const std::string_view bytes(compiled.bytes + compiled.offsets[k], compiled.offsets[k + 1] - compiled.offsets[k]);
    const ComponentType type = DeserializeComponentType(bytes);
    EXPECT_NE(BuiltinLibrary().FindComponent(type.name), nullptr) << type.name;
    ++types;
  }
  EXPECT_EQ(types, BuiltinLibrary().ComponentNames().size());
  EXPECT_EQ(parsed.library_hash, compiled.library_hash);
}

TEST(CompiledTypesTest, ATypeReadBackKeepsItsLocationsAndSharedExpressions) {
  const ComponentType* mass = BuiltinLibrary().FindComponent("Mass");
  ASSERT_NE(mass, nullptr);
  const ComponentType copy = DeserializeComponentType(SerializeComponentType(*mass));
  EXPECT_EQ(copy.name, mass->name);
  ASSERT_EQ(copy.equations.size(), mass->equations.size());
  for (size_t k = 0; k < copy.equations.size(); ++k) {
    EXPECT_EQ(copy.equations[k].text, mass->equations[k].text);
    EXPECT_EQ(copy.equations[k].loc.ToString(), mass->equations[k].loc.ToString());
    EXPECT_EQ(AstToString(*copy.equations[k].ast.rhs), AstToString(*mass->equations[k].ast.rhs));
  }
  EXPECT_EQ(copy.loc.ToString(), mass->loc.ToString());
  EXPECT_NE(copy.loc.ToString().find("components/"), std::string::npos);

  // Two fields that point to one expression still do after the round trip.
  ComponentType shared;
  shared.name = "Shared";
  const AstPtr one = MakeAst(Ast::Kind::kNumber, 0, "", {});
  shared.parameters.resize(2);
  shared.parameters[0].value = one;
  shared.parameters[1].value = one;
  const ComponentType back = DeserializeComponentType(SerializeComponentType(shared));
  EXPECT_EQ(back.parameters[0].value, back.parameters[1].value);
}

TEST(CompiledTypesTest, BytesCutShortAreRefused) {
  const std::string bytes = SerializeComponentType(*BuiltinLibrary().FindComponent("SpringDamper"));
  for (const size_t keep : {size_t{0}, size_t{3}, bytes.size() / 2, bytes.size() - 1}) {
    try {
      DeserializeComponentType(bytes.substr(0, keep));
      ADD_FAILURE() << "read " << keep << " of " << bytes.size() << " bytes";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "compiled type: the bytes end early");
    }
  }
  EXPECT_THROW(DeserializeComponentType(bytes + "x"), std::runtime_error);
}

TEST(CompiledTypesTest, TypesCompiledFromOtherLibraryTextAreNotUsed) {
  CompiledLibraryTypes other = CompiledBuiltinTypes();
  other.library_hash ^= 1;
  EXPECT_FALSE(UseCompiledLibraryTypes(other));
  other = CompiledBuiltinTypes();
  other.entries -= 1;
  EXPECT_FALSE(UseCompiledLibraryTypes(other));
}

}  // namespace
}  // namespace momenta
