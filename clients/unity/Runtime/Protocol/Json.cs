using System;
using System.IO;
using Newtonsoft.Json;
using Newtonsoft.Json.Linq;

namespace Toyroom.Protocol
{
    /// <summary>
    /// The JSON settings the brain expects: nulls written (an absent <c>holding</c> is
    /// <c>null</c>, never <c>""</c>), unknown fields ignored (a newer minor version may add
    /// some), numbers as the schemas say. Use these rather than Newtonsoft's defaults.
    /// </summary>
    public static class ToyroomJson
    {
        public static readonly JsonSerializerSettings Settings = new JsonSerializerSettings
        {
            NullValueHandling = NullValueHandling.Include,
            MissingMemberHandling = MissingMemberHandling.Ignore,
            DateParseHandling = DateParseHandling.None,
            FloatParseHandling = FloatParseHandling.Double,
            Formatting = Formatting.None,
        };

        public static readonly JsonSerializer Serializer = JsonSerializer.Create(Settings);

        /// <summary>A message as JSON text.</summary>
        public static string Write(object message)
        {
            return JsonConvert.SerializeObject(message, Settings);
        }

        /// <summary>A message as a JSON object (to embed in a gateway frame).</summary>
        public static JObject ToObject(object message)
        {
            return JObject.FromObject(message, Serializer);
        }

        /// <summary>JSON text or a JSON object read as <typeparamref name="T"/>.</summary>
        public static T Read<T>(string json)
        {
            return JsonConvert.DeserializeObject<T>(json, Settings);
        }

        public static T Read<T>(JToken json)
        {
            return json.ToObject<T>(Serializer);
        }

        /// <summary>The <c>type</c> of a message (its envelope), or null.</summary>
        public static string TypeOf(JToken message)
        {
            var obj = message as JObject;
            return obj == null ? null : (string)obj["type"];
        }

        /// <summary>Whether <paramref name="version"/> ("1.3") has this SDK's major version.</summary>
        public static bool SameMajor(string version)
        {
            if (string.IsNullOrEmpty(version)) return false;
            var ours = Version.Protocol.Split('.')[0];
            return version.Split('.')[0] == ours;
        }
    }
}
