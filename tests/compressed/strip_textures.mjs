// Drops every texture, image and material of a glTF file (the geometry,
// skin and animation stay): the compressed test files hold what the
// loaders read and little else. Usage: node strip_textures.mjs IN OUT
import { NodeIO } from '@gltf-transform/core';
import { ALL_EXTENSIONS } from '@gltf-transform/extensions';
import { prune } from '@gltf-transform/functions';

const [input, output] = process.argv.slice(2);
const io = new NodeIO().registerExtensions(ALL_EXTENSIONS);
const document = await io.read(input);
for (const material of document.getRoot().listMaterials()) material.dispose();
for (const texture of document.getRoot().listTextures()) texture.dispose();
await document.transform(prune());
await io.write(output, document);
