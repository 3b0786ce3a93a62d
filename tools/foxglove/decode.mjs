// How long Foxglove's decoder takes over one frame of spheres (issue 30, item 3): the first
// /scene message of a wetbounce MCAP decoded by protobufjs from the schema the file carries,
// as Foxglove and Lichtblick decode protobuf channels, four times. It separates the decoding,
// which a browser pays on any machine, from the drawing, which a GPU does.
//
//   npm install @mcap/core@2 protobufjs@7 fzstd@0.1     (in this folder, once)
//   node tools/foxglove/decode.mjs FILE.mcap [TOPIC]     (default /scene)
import fs from "node:fs";
import { McapIndexedReader } from "@mcap/core";
import protobuf from "protobufjs";
import descriptor from "protobufjs/ext/descriptor/index.js";
import { decompress } from "fzstd";

const [file, topic = "/scene"] = process.argv.slice(2);
if (!file) {
  console.error("usage: node decode.mjs FILE.mcap [TOPIC]");
  process.exit(2);
}
const fh = await fs.promises.open(file, "r");
const size = BigInt((await fh.stat()).size);
const readable = {
  size: async () => size,
  read: async (offset, length) => {
    const buf = new Uint8Array(Number(length));
    await fh.read(buf, 0, Number(length), Number(offset));
    return buf;
  },
};
const reader = await McapIndexedReader.Initialize({
  readable,
  decompressHandlers: { zstd: (data, decompressedSize) => decompress(data, new Uint8Array(Number(decompressedSize))) },
});
for await (const message of reader.readMessages({ topics: [topic] })) {
  const channel = reader.channelsById.get(message.channelId);
  const schema = reader.schemasById.get(channel.schemaId);
  const root = protobuf.Root.fromDescriptor(descriptor.FileDescriptorSet.decode(schema.data));
  const type = root.lookupType(schema.name);
  for (let k = 0; k < 4; k++) {
    const t0 = process.hrtime.bigint();
    const decoded = type.toObject(type.decode(message.data), { defaults: true });
    const ms = Number(process.hrtime.bigint() - t0) / 1e6;
    const n = decoded.entities?.reduce((sum, e) => sum + e.spheres.length, 0);
    console.log(`${topic}: ${message.data.length} B${n === undefined ? "" : `, ${n} spheres`}: decoded in ${ms.toFixed(0)} ms`);
  }
  break;
}
await fh.close();
