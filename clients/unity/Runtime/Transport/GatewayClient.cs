using System;
using System.Collections.Concurrent;
using System.Collections.Generic;
using System.IO;
using System.Net.WebSockets;
using System.Text;
using System.Threading;
using Newtonsoft.Json.Linq;
using Toyroom.Gateway;
using Toyroom.Protocol;

namespace Toyroom.Transport
{
    /// <summary>Why the gateway would not take a hello (wrong token, bad name...).</summary>
    public sealed class GatewayRefused : Exception
    {
        public GatewayRefused(string message) : base(message) { }
    }

    /// <summary>
    /// One world's protocol through <c>toyroom gateway</c>, over .NET's ClientWebSocket alone
    /// (no native plugin; runs in the editor, players and under Mono). Frames are
    /// protocol/README.md's "The gateway's frames". Handlers run on the receive thread:
    /// hand them to the main thread (EngineHost does). Sends are queued and written in
    /// order by a sender thread, so any thread may send without blocking on the network.
    /// </summary>
    public sealed class GatewayClient : IDisposable
    {
        private readonly Uri url;
        private ClientWebSocket socket;
        private readonly BlockingCollection<string> outbox = new BlockingCollection<string>();
        private readonly Dictionary<long, Action<Query>> served = new Dictionary<long, Action<Query>>();
        private readonly Dictionary<long, Action<Sample>> subscribed = new Dictionary<long, Action<Sample>>();
        private readonly object gate = new object();
        private readonly CancellationTokenSource stop = new CancellationTokenSource();
        private long nextId;
        private Thread receiver;
        private Thread sender;

        /// <summary>The gateway's welcome (world, prefix, versions) once connected.</summary>
        public Welcome Welcome { get; private set; }

        /// <summary>An error frame from the gateway (a refused frame); on the receive thread.</summary>
        public event Action<FrameError> Refused;

        /// <summary>The connection ended (its reason); on the receive thread.</summary>
        public event Action<string> Closed;

        /// <summary>Whether the socket is open.</summary>
        public bool IsOpen { get { return socket != null && socket.State == WebSocketState.Open; } }

        public GatewayClient(string url)
        {
            this.url = new Uri(url);
        }

        /// <summary>Whether Nagle's algorithm could be turned off on the socket (see <see cref="NoDelay"/>).</summary>
        public bool NagleOff { get; private set; }

        /// <summary>
        /// Turn Nagle's algorithm off on the socket under <paramref name="root"/>. Mono's
        /// ClientWebSocket leaves it on, so a tick's second small frame waits for the first to be
        /// acknowledged, and the gateway acknowledges late (40 ms a tick on Linux). .NET exposes no
        /// option for it, so this looks for the Socket among the websocket's fields, a few levels
        /// deep, whatever the runtime names them.
        /// </summary>
        private static bool NoDelay(object root, int depth)
        {
            if (root == null || depth > 4) return false;
            var socket = root as System.Net.Sockets.Socket;
            if (socket != null)
            {
                socket.NoDelay = true;
                return true;
            }
            const System.Reflection.BindingFlags all = System.Reflection.BindingFlags.Instance
                | System.Reflection.BindingFlags.NonPublic | System.Reflection.BindingFlags.Public;
            for (var type = root.GetType(); type != null && type != typeof(object); type = type.BaseType)
            {
                foreach (var field in type.GetFields(all))
                {
                    if (field.FieldType.IsPrimitive || field.FieldType == typeof(string)) continue;
                    if (field.FieldType.IsValueType || field.FieldType.IsArray) continue;
                    if (NoDelay(field.GetValue(root), depth + 1)) return true;
                }
            }
            return false;
        }

        /// <summary>
        /// Connect and say hello as <paramref name="role"/>/<paramref name="name"/>; retries a
        /// refused connection (the gateway may still be starting) until <paramref name="timeout"/>.
        /// </summary>
        /// <exception cref="GatewayRefused">the gateway answered the hello with an error.</exception>
        /// <exception cref="TimeoutException">no gateway answered in time.</exception>
        public void Connect(string role, string name, string token, TimeSpan timeout)
        {
            var deadline = DateTime.UtcNow + timeout;
            while (true)
            {
                socket = new ClientWebSocket();
                try
                {
                    socket.ConnectAsync(url, stop.Token).Wait();
                    NagleOff = NoDelay(socket, 0);
                    break;
                }
                catch (AggregateException)
                {
                    socket.Dispose();
                    if (DateTime.UtcNow > deadline) throw new TimeoutException("no gateway answers at " + url);
                    Thread.Sleep(100);
                }
            }
            var hello = new GatewayHello { Role = role, Name = name, Token = token, Client = "toyroom C# SDK" };
            SendNow(ToyroomJson.Write(hello));
            var first = JObject.Parse(ReceiveText());
            if ((string)first["op"] != "welcome")
                throw new GatewayRefused((string)first["message"] ?? first.ToString());
            Welcome = first.ToObject<Welcome>(ToyroomJson.Serializer);
            sender = new Thread(SendLoop) { IsBackground = true, Name = "toyroom gateway sender" };
            receiver = new Thread(ReceiveLoop) { IsBackground = true, Name = "toyroom gateway receiver" };
            sender.Start();
            receiver.Start();
        }

        /// <summary>Publish <paramref name="message"/> on <paramref name="key"/> (relative to the world).</summary>
        public void Put(string key, object message)
        {
            Send(new Put { Key = key, Payload = ToyroomJson.ToObject(message) });
        }

        /// <summary>Answer queries on <paramref name="key"/> with <paramref name="onQuery"/>.</summary>
        public long Serve(string key, Action<Query> onQuery)
        {
            long id;
            lock (gate) { id = ++nextId; served[id] = onQuery; }
            Send(new Serve { Id = id, Key = key });
            return id;
        }

        /// <summary>Call <paramref name="onSample"/> for every message on <paramref name="key"/>.</summary>
        public long Subscribe(string key, Action<Sample> onSample)
        {
            long id;
            lock (gate) { id = ++nextId; subscribed[id] = onSample; }
            Send(new Subscribe { Id = id, Key = key });
            return id;
        }

        /// <summary>Answer query <paramref name="qid"/>; <paramref name="ok"/> false sends an error reply.</summary>
        public void Reply(long qid, object message, bool ok)
        {
            Send(new Reply { Qid = qid, Payload = ToyroomJson.ToObject(message), Ok = ok });
        }

        private List<string> held;

        /// <summary>
        /// Hold frames until <see cref="Flush"/>, then send them as one <c>batch</c> (one
        /// WebSocket message: a tick's events, statuses, state and the step's reply together).
        /// </summary>
        public void Hold()
        {
            lock (gate) { if (held == null) held = new List<string>(); }
        }

        /// <summary>Send what <see cref="Hold"/> held, as one message, and stop holding.</summary>
        public void Flush()
        {
            List<string> frames;
            lock (gate) { frames = held; held = null; }
            if (frames == null || frames.Count == 0 || outbox.IsAddingCompleted) return;
            outbox.Add(frames.Count == 1 ? frames[0] : "{\"op\":\"batch\",\"frames\":[" + string.Join(",", frames) + "]}");
        }

        private void Send(object frame)
        {
            var text = ToyroomJson.Write(frame);
            lock (gate)
            {
                if (held != null)
                {
                    held.Add(text);
                    return;
                }
            }
            if (!outbox.IsAddingCompleted) outbox.Add(text);
        }

        private void SendNow(string text)
        {
            var bytes = Encoding.UTF8.GetBytes(text);
            socket.SendAsync(new ArraySegment<byte>(bytes), WebSocketMessageType.Text, true, stop.Token).Wait();
        }

        private void SendLoop()
        {
            try
            {
                foreach (var text in outbox.GetConsumingEnumerable(stop.Token)) SendNow(text);
            }
            catch (OperationCanceledException) { }
            catch (AggregateException) { }
            catch (InvalidOperationException) { }
        }

        private string ReceiveText()
        {
            var buffer = new ArraySegment<byte>(new byte[64 * 1024]);
            using (var message = new MemoryStream())
            {
                while (true)
                {
                    var part = socket.ReceiveAsync(buffer, stop.Token).Result;
                    if (part.MessageType == WebSocketMessageType.Close) return null;
                    message.Write(buffer.Array, 0, part.Count);
                    if (part.EndOfMessage) return Encoding.UTF8.GetString(message.ToArray());
                }
            }
        }

        private void ReceiveLoop()
        {
            var reason = "the gateway closed the connection";
            try
            {
                string text;
                while ((text = ReceiveText()) != null) Dispatch(JObject.Parse(text));
            }
            catch (Exception error)
            {
                reason = stop.IsCancellationRequested ? "closed" : "connection lost: " + error.GetBaseException().Message;
            }
            outbox.CompleteAdding();
            var closed = Closed;
            if (closed != null) closed(reason);
        }

        private void Dispatch(JObject frame)
        {
            var op = (string)frame["op"];
            if (op == "query")
            {
                var query = frame.ToObject<Query>(ToyroomJson.Serializer);
                Action<Query> handler;
                lock (gate) served.TryGetValue(query.Serve, out handler);
                if (handler != null) handler(query);
            }
            else if (op == "sample")
            {
                var sample = frame.ToObject<Sample>(ToyroomJson.Serializer);
                Action<Sample> handler;
                lock (gate) subscribed.TryGetValue(sample.Sub, out handler);
                if (handler != null) handler(sample);
            }
            else if (op == "error")
            {
                var refused = Refused;
                if (refused != null) refused(frame.ToObject<FrameError>(ToyroomJson.Serializer));
            }
        }

        /// <summary>Close the connection (the gateway withdraws this node's liveliness token).</summary>
        public void Close()
        {
            if (socket == null) return;
            outbox.CompleteAdding();
            if (sender != null) sender.Join(1000);
            try
            {
                if (socket.State == WebSocketState.Open)
                    socket.CloseAsync(WebSocketCloseStatus.NormalClosure, "bye", CancellationToken.None).Wait(1000);
            }
            catch (Exception) { }
            stop.Cancel();
        }

        public void Dispose()
        {
            Close();
            if (socket != null) socket.Dispose();
        }
    }
}
