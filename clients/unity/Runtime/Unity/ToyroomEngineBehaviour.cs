#if UNITY_5_3_OR_NEWER
using System;
using Toyroom.Engine;
using Toyroom.Transport;
using UnityEngine;

namespace Toyroom.Unity
{
    /// <summary>
    /// The thin Unity adapter: connects to <c>toyroom gateway</c> on Start, and on every
    /// FixedUpdate runs what the brain asked for on Unity's main thread (handshakes, resets,
    /// commands, and up to <see cref="ticksPerFixedUpdate"/> ticks of a pending step). Put it on
    /// a GameObject next to a component that implements <see cref="IEngine"/> (your scene's
    /// game logic), or set <see cref="Engine"/> from code. Everything else is the Mono-testable
    /// core (EngineHost, GatewayClient), which the toyroom repository tests under Mono.
    /// </summary>
    public sealed class ToyroomEngineBehaviour : MonoBehaviour
    {
        [Tooltip("The gateway: toyroom gateway --world W --listen ws://127.0.0.1:7448")]
        public string gatewayUrl = "ws://127.0.0.1:7448";

        [Tooltip("This engine's name in the world (letters, digits, '_' or '-')")]
        public string engineName = "unity";

        [Tooltip("The gateway's --token file content, if it has one")]
        public string token = "";

        [Tooltip("Ticks of a lock-step 'step' run per FixedUpdate (pace the game, or run ahead)")]
        public int ticksPerFixedUpdate = 1;

        /// <summary>The game; found on this GameObject when not set.</summary>
        public IEngine Engine;

        private GatewayClient gateway;
        private EngineHost host;

        private void Start()
        {
            if (Engine == null) Engine = GetComponent<IEngine>();
            if (Engine == null)
            {
                Debug.LogError("ToyroomEngineBehaviour: no component implementing Toyroom.Engine.IEngine here");
                enabled = false;
                return;
            }
            gateway = new GatewayClient(gatewayUrl);
            gateway.Closed += reason => Debug.LogWarning("toyroom: " + reason);
            try
            {
                gateway.Connect("engine", engineName, string.IsNullOrEmpty(token) ? null : token, TimeSpan.FromSeconds(5));
            }
            catch (Exception error)
            {
                Debug.LogError("toyroom: cannot join the gateway at " + gatewayUrl + ": " + error.Message);
                enabled = false;
                return;
            }
            host = new EngineHost(Engine, gateway) { Log = Debug.LogWarning };
            host.Start();
            Debug.Log("toyroom: engine '" + engineName + "' joined world '" + gateway.Welcome.World + "'");
        }

        private void FixedUpdate()
        {
            if (host != null) host.Pump(ticksPerFixedUpdate);
        }

        private void OnDestroy()
        {
            if (gateway != null) gateway.Dispose();
        }
    }
}
#endif
